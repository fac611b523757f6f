/* gear_dyn native FMU kernel: the single-DOF gear mesh model (gd_kernel.c) and the two-DOF
 * torsional model (gd_torsional.c) stepped from tables in mesh phase. The single-DOF model:
 *
 *   m x'' + c (x' - f_m e'(p)) + k(p) f(x - e(p)) = W,   p' = f_m = z1 w1 / (2 pi),  W = T1 / r_b1
 *
 * f is the identity, or the backlash dead zone of half gap b. k, e and de/dp are polynomials of
 * the phase on each piece of one mesh cycle (data in model_data.c, written by gear_dyn). C99,
 * libm only. The kernel version is GD_KERNEL_VERSION; model_data.c states the table format.
 * The torsional model (gd_model.tors not NULL) is described in gd_torsional.c. */
#ifndef GD_KERNEL_H
#define GD_KERNEL_H

#include <stddef.h>

#define GD_KERNEL_VERSION "1.1.0"
#define GD_TABLE_FORMAT 3

/* parameters and inputs, in this order (value references 1..5) */
enum { GD_SPEED, GD_TORQUE, GD_ZETA, GD_HALF_GAP, GD_TOL, GD_NPAR };
/* outputs (value references 6..11) */
enum { GD_X, GD_V, GD_DTE, GD_FORCE, GD_K, GD_DRIVEN, GD_NOUT };
/* outputs of the torsional model (value references 6..18) */
enum { GT_Q1, GT_Q2, GT_V1, GT_V2, GT_DTE, GT_DELTA, GT_FORCE, GT_K, GT_W1, GT_W2, GT_ECC,
       GT_TF1, GT_TF2, GT_NOUT };
#define GD_MAX_OUT GT_NOUT

typedef struct {
    const char *name, *unit;
    double low, high;   /* valid range */
    int low_open;       /* 1: low itself is refused */
} gd_param;

#define GD_NKIN 7               /* e_ecc, travel - p p_bt, L_AC, L_CD, L_CP, foot1, foot2 (m) */

typedef struct {                /* the contact-line form of an eccentric pair (gd_torsional.c) */
    int n_terms;                /* the non-zero Fourier terms, by rising harmonic k */
    double period;              /* P, the hunting period in mesh cycles */
    const unsigned short *term_k;   /* harmonic k of each term: cos, sin of 2 pi k p / P */
    const unsigned char *term_q;    /* its quantity, 0 .. GD_NKIN - 1 */
    const double *term_ab;      /* [n_terms][cos, sin] amplitudes (m) */
    double pitch, width, sin_bb, face_width, l_ac0;   /* the contact-line layout (m) */
    int index0, n_index;        /* contact-line pair indices evaluated */
    double per_length;          /* k_l (N/m^2): k = k_l L */
    double mu;                  /* friction coefficient; < 0: no friction */
} gd_lines;

typedef struct {                /* the torsional model's constants (gd_torsional.c) */
    double inertia[2];          /* I1, I2 (kg m^2) */
    double z2;                  /* gear teeth (nominal w2 = w1 z1 / z2) */
    double arm[2];              /* mean friction arms (m): W = T1 / (r_b1 - arm1) */
    double load_fixed;          /* T2 (N m); < 0: T2 = W (r_b2 + arm2) */
    double q_scale[4];          /* state scales of the error control (rad, rad/s) */
    const gd_lines *lines;      /* NULL: coef holds the polynomials; else e, de/dp, k, phi1,
                                 * phi2 come from these series and the contact lines */
} gd_tors;

typedef struct {
    int format;                 /* GD_TABLE_FORMAT */
    int n_pieces, degree;       /* pieces over one mesh cycle, polynomial degree */
    int has_te, has_backlash;
    const double *breaks;       /* n_pieces + 1 phases from 0 to 1 (cycles) */
    const double *coef;         /* [piece][k, e, de/dp][degree + 1], Horner order in s in [-1, 1] */
    const unsigned char *flat;  /* 1: k and e constant and de/dp = 0 on the piece */
    const gd_param *params;     /* GD_NPAR names, units and ranges */
    double start[GD_NPAR];      /* start values of the parameters and inputs */
    double mass, k_mean, rb1, rb2, z1, phase0, x_scale;
    const gd_tors *tors;        /* NULL: the single-DOF model; else the torsional model, whose
                                 * coef holds [e, de/dp, k, phi1, phi2] per piece and whose
                                 * breaks run from 0 to the table period (cycles) */
} gd_model;

extern const gd_model gd_model_data;

typedef struct {
    double par[GD_NPAR];        /* parameters and inputs */
    double t, x, v;             /* time (s), DTE (m) and its rate (m/s) */
    double frac;                /* mesh phase modulo the table's span (cycles) */
    double h;                   /* next Runge-Kutta step (s) */
    double q[4];                /* torsional states q1, q2 (rad), q1', q2' (rad/s) */
    int piece, regime;          /* table piece; contact 1 drive, 0 gap, -1 back flank */
    long n_events;
} gd_state;

enum { GD_OK = 0, GD_ERR_RANGE = 1, GD_ERR_STEP = 2, GD_ERR_VR = 3 };

/* the message of a failed step (both FMI versions log it) */
#define GD_STEP_MESSAGE "gear_dyn kernel: step failed (step size underflow or too many " \
    "contact changes); lower solver.tolerance or check the inputs"

void gd_defaults(gd_state *s, const gd_model *m);
void gd_start(gd_state *s, const gd_model *m, double t0);
int gd_advance(gd_state *s, const gd_model *m, double t_end);
void gd_outputs(const gd_state *s, const gd_model *m, double *out);
/* the torsional model (gd_torsional.c), called by the functions above */
void gd_tors_start(gd_state *s, const gd_model *m, double t0);
/* the Dormand-Prince 5(4) pair both kernels step with (gd_kernel.c), and the weights of its
 * continuous extension (dense output of order 4) */
extern const double gd_dp_a[7][6], gd_dp_c[7], gd_dp_err[7], gd_dp_dense[7];

int gd_tors_advance(gd_state *s, const gd_model *m, double t_end);
void gd_tors_outputs(const gd_state *s, const gd_model *m, double *out);
/* e, de/dp, k, phi1, phi2 of the table at the state's time and phase */
void gd_tors_coef(const gd_state *s, const gd_model *m, double v[5]);
/* e, de/dp, k, phi1, phi2 of the contact-line form at mesh phase p (cycles, any real) */
void gd_lines_eval(const gd_lines *g, double p, double v[5]);

/* the solvers' kernel method (gd_run.c; not in the FMU): from s, advance to each of the n
 * non-decreasing times t and store the states there, y[i][2] = (x, v) or y[i][4] = q, and for
 * the torsional model, where coef is not NULL, its table's values there, coef[i][5] (e, de/dp,
 * k, phi1, phi2); returns the samples stored (n, or fewer with *status GD_ERR_STEP: a failed
 * step or a non-finite state) */
long gd_run(gd_state *s, const gd_model *m, long n, const double *t, double *y, double *coef,
            int *status);
/* gd_run's torsional model (gd_torsional.c): steps end at piece edges only, the outputs come
 * from each step's dense output */
long gd_tors_run(gd_state *s, const gd_model *m, long n, const double *t, double *y,
                 double *coef, int *status);

/* the FMI glue of both versions: values by value reference (0 time, 1..GD_NPAR the parameters
 * and inputs, then the outputs); gd_set writes one message into msg on a refused value */
int gd_get(const gd_state *s, const gd_model *m, const unsigned *vr, size_t n, double *v);
int gd_set(gd_state *s, const gd_model *m, unsigned vr, double value, int started, char *msg,
           size_t len);

#endif
