/* The drivetrain interface of the native FMU (gd_drive.c): the two-DOF torsional mesh with a
 * torque input on each shaft and the angles and speeds of both shafts as outputs, stepped from
 * the same tables as the pinion-speed interface. Its model_data.c defines gd_drive_data. */
#ifndef GD_DRIVE_H
#define GD_DRIVE_H

#include "gd_kernel.h"

/* value references: 1 pinion.torque (speed_in: pinion.speed), 2 gear.torque (inputs),
 * 3 damping.ratio,
 * 4 backlash.half_gap, 5 solver.tolerance, 6 inertia.pinion, 7 inertia.gear,
 * 8 pinion.speed_start (parameters), then the outputs */
enum { GV_T1, GV_T2, GV_ZETA, GV_HALF_GAP, GV_TOL, GV_I1, GV_I2, GV_W0, GV_NPAR };
enum { GV_A1, GV_W1, GV_A2, GV_W2, GV_FORCE, GV_DTE, GV_NOUT };

struct gd_drive {
    int speed_in;               /* 1: the pinion is driven by speed (value reference 1 is its
                                 * speed, the output GV_W1 the torque it takes), 0: by torque */
    int nq;                     /* quantities per piece in gd_model.coef (3 or 5) */
    int idx[5];                 /* where e, de/dp, k, phi1, phi2 are among them (-1: zero) */
    double sign_e;              /* F = k f(u + sign_e e) + c (u' + sign_e f_m de/dp) */
    double period;              /* table span, mesh cycles (breaks run from 0 to it) */
    const gd_param *params;     /* GV_NPAR names, units and ranges */
    double start[GV_NPAR];      /* their start values */
    double q_scale[4];          /* error-control scales of the angles (rad) and speeds (rad/s) */
};
typedef struct gd_drive gd_drive;

/* NULL: the pinion-speed interface; else this FMU's drivetrain constants (model_data.c) */
extern const gd_drive *const gd_drive_data;

/* the drivetrain state: the kernel's (time, phase, piece, step size, q = angles and speeds)
 * and the drivetrain's parameters and inputs */
typedef struct {
    gd_state k;
    double par[GV_NPAR];
} gd_dstate;

void gd_drive_defaults(gd_dstate *s, const gd_model *m, const gd_drive *d);
void gd_drive_start(gd_dstate *s, const gd_model *m, const gd_drive *d, double t0);
int gd_drive_advance(gd_dstate *s, const gd_model *m, const gd_drive *d, double t_end);
int gd_drive_get(const gd_dstate *s, const gd_model *m, const gd_drive *d, const unsigned *vr,
                 size_t n, double *v);
int gd_drive_set(gd_dstate *s, const gd_drive *d, unsigned vr, double value, int started,
                 char *msg, size_t len);

#endif
