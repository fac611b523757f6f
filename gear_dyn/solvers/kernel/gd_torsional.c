/* gear_dyn native FMU kernel: the two-DOF torsional model with eccentricity and friction
 * (gear_dyn.models.torsional), states y = [q1, q2, q1', q2'] about the nominal rotation:
 *
 *   I1 q1'' = T1 - r_b1 F + max(F, 0) phi1(p),   I2 q2'' = r_b2 F - T2 + max(F, 0) phi2(p)
 *   F = k(p) (r_b1 q1 - r_b2 q2 + e(p)) + c (r_b1 q1' - r_b2 q2' + f_m de/dp),
 *   p' = f_m = z1 w1 / (2 pi),  c = 2 xi sqrt(m_e k_m)
 *
 * e, de/dp, k, phi1, phi2 are polynomials of the mesh phase p on each piece of the table (its
 * breaks are the switching instants; data in model_data.c, written by gear_dyn), or, for an
 * eccentric pair with contact-line stiffness (gd_tors.lines), they come from Fourier series of
 * the kinematics over the hunting period and the contact-line overlap of Liu et al. (2017),
 * eqs. 14-27 (gear_dyn.eccentricity.contact_lines and .friction); over each stretch of a
 * piece the kernel steps at once, the series are replaced by their Taylor polynomials about the
 * stretch's middle (lines_expand), of the lowest degree whose remainder bound is below
 * GD_LOCAL_ERROR of the displacement scale, else summed directly. Each piece is
 * stepped by the Dormand-Prince 5(4) pair with error control (Hairer, Norsett & Wanner 1993);
 * piece edges are time events and a communication point ends the last step exactly. */
#include <math.h>
#include <string.h>
#include "gd_kernel.h"

#define PI 3.14159265358979323846
#define NQ 5

#define NX (GD_NKIN + 1)          /* the kinematics and de_ecc/dp */
#define MAX_LOCAL 8               /* highest degree of the local Taylor polynomials */
#define GD_LOCAL_ERROR 1e-13      /* their remainder bound, relative to the displacement scale */

typedef struct {                 /* the contact-line form's kinematics near a phase */
    int degree;                  /* -1: none (sum the series) */
    double pm;                   /* the expansion's centre (cycles) */
    double c[NX][MAX_LOCAL + 1]; /* Taylor coefficients in p - pm, ascending powers (m, m/cycle) */
} lexp;

typedef struct {                 /* one piece at constant inputs */
    const gd_model *m;
    const double *c;             /* the piece's coefficients [NQ][degree + 1] */
    double a, b;                 /* its phase edges */
    double t0, p0, fm, cd, t1, t2;
    double t1_end;               /* gd_tors_run: the stretch's end time, exact (t0 + dt is not) */
    double s0, s1;               /* the local variable s = s0 + s1 (t - t0) on the piece */
    double inv1, inv2;           /* 1 / I1, 1 / I2 */
    int degree;
    const gd_lines *lines;
    lexp x;                      /* the contact-line form's local kinematics */
} tctx;

/* e, de/dp, k, phi1, phi2 at phase p of the contact-line form: the kinematic series (cos k th,
 * sin k th by rotation) and the overlap of each contact line with the field of contact, split
 * at the pitch line (gear_dyn.eccentricity.friction.line_state_scalar); the drivetrain
 * interface (gd_drive.c) evaluates the same */
/* e, de/dp, k, phi1, phi2 at phase p from the kinematics kin[GD_NKIN] (travel less its mean
 * growth p p_bt) and de_ecc/dp */
static void overlap(const gd_lines *g, const double *kin, double dedp, double p, double v[NQ])
{
    double travel, d, total = 0.0, t1 = 0.0, t2 = 0.0;
    double l_ac, l_cd, l_cp, f1, f2, w = g->width;
    int k;
    travel = kin[1] + p * g->pitch;
    l_ac = kin[2];
    l_cd = kin[3];
    l_cp = kin[4];
    f1 = kin[5];
    f2 = kin[6];
    d = travel - g->pitch * floor(travel / g->pitch) - g->pitch + g->l_ac0 - l_ac
        + g->index0 * g->pitch;
    for (k = 0; k < g->n_index; k++, d += g->pitch) {
        if (w == 0.0) {
            if (0.0 <= d && d < l_cd) {
                double b = g->face_width, mid = d + l_ac, sg = d < l_cp ? -1.0 : 1.0;
                total += b;
                t1 -= sg * b * (mid - f1);
                t2 += sg * b * (f2 - mid);
            }
        } else {
            double back = d - w, lo2 = fmax(back, 0.0), hi2 = fmin(d, l_cp);
            double lo1 = fmax(back, l_cp), hi1 = fmin(d, l_cd);
            if (hi2 > lo2) {
                double sg = (hi2 - lo2) / g->sin_bb, mid = 0.5 * (lo2 + hi2) + l_ac;
                total += sg;
                t1 += sg * (mid - f1);
                t2 -= sg * (f2 - mid);
            }
            if (hi1 > lo1) {
                double sg = (hi1 - lo1) / g->sin_bb, mid = 0.5 * (lo1 + hi1) + l_ac;
                total += sg;
                t1 -= sg * (mid - f1);
                t2 += sg * (f2 - mid);
            }
        }
    }
    v[0] = kin[0];
    v[1] = dedp;
    v[2] = g->per_length * total;
    v[3] = g->mu >= 0.0 && total > 0.0 ? g->mu / total * t1 : 0.0;
    v[4] = g->mu >= 0.0 && total > 0.0 ? g->mu / total * t2 : 0.0;
}

/* the series' terms in order, each with cos and sin of its harmonic k of th (by rotation:
 * both sums below walk the terms so) */
typedef struct {
    const gd_lines *g;
    int i, k;                    /* the next term, the harmonic of ck, sk */
    double c1, s1, ck, sk;       /* cos, sin of th and of k th */
} terms;

static void terms_start(terms *it, const gd_lines *g, double th)
{
    it->g = g;
    it->i = it->k = 0;
    it->c1 = cos(th);
    it->s1 = sin(th);
    it->ck = 1.0;
    it->sk = 0.0;
}

/* the next term's amplitudes (a, b), it->k its harmonic, it->ck, it->sk cos and sin of k th;
 * NULL after the last */
static const double *terms_next(terms *it)
{
    if (it->i >= it->g->n_terms) return 0;
    while (it->k < it->g->term_k[it->i]) {
        double cn = it->ck * it->c1 - it->sk * it->s1;
        it->sk = it->sk * it->c1 + it->ck * it->s1;
        it->ck = cn;
        it->k++;
    }
    return it->g->term_ab + 2 * it->i++;
}

void gd_lines_eval(const gd_lines *g, double p, double v[NQ])
{
    double kin[GD_NKIN] = {0.0}, rate = 0.0;
    const double *ab;
    terms it;
    terms_start(&it, g, 2.0 * PI * p / g->period);
    while ((ab = terms_next(&it)) != 0) {
        int q = g->term_q[it.i - 1];
        kin[q] += ab[0] * it.ck + ab[1] * it.sk;
        if (q == 0) rate += it.k * (ab[1] * it.ck - ab[0] * it.sk);
    }
    overlap(g, kin, rate * 2.0 * PI / g->period, p, v);
}

/* the Taylor polynomials of the kinematics and de_ecc/dp about pm for |p - pm| <= r: each term
 * a cos(k w p) + b sin(k w p), w = 2 pi / P, is Re z e^{i k w s}, z = (a - i b) e^{i k w pm},
 * s = p - pm, whose degree-n Taylor coefficient is Re z (i k w)^n / n! and whose remainder after
 * degree n is at most |z| (k w r)^(n + 1) / (n + 1)! (Lagrange). The lowest degree whose summed
 * bound is below tol for every quantity, else x->degree = -1 (the series summed directly). */
static void lines_expand(const gd_lines *g, double pm, double r, double tol, lexp *x)
{
    double w = 2.0 * PI / g->period;
    static const double inv[MAX_LOCAL + 3] = {1.0, 1.0, 1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5,
                                              1.0 / 6, 1.0 / 7, 1.0 / 8, 1.0 / 9, 1.0 / 10};
    double bound[NX][MAX_LOCAL + 1];
    const double *ab;
    terms it;
    int n, q;
    memset(x->c, 0, sizeof x->c);
    memset(bound, 0, sizeof bound);
    x->pm = pm;
    x->degree = -1;
    terms_start(&it, g, w * pm);
    while ((ab = terms_next(&it)) != 0) {
        double f = it.k * w;
        double zr = ab[0] * it.ck + ab[1] * it.sk, zi = ab[0] * it.sk - ab[1] * it.ck;
        int rows = g->term_q[it.i - 1] == 0 ? 2 : 1, row;
        for (row = 0; row < rows; row++) {
            /* row 1: de_ecc/dp, the term's derivative, z i k w */
            double yr = row ? -zi * f : zr, yi = row ? zr * f : zi;
            double rem = sqrt(yr * yr + yi * yi) * f * r;
            q = row ? GD_NKIN : g->term_q[it.i - 1];
            for (n = 0; n <= MAX_LOCAL; n++) {
                double t = yr, fn = f * inv[n + 1];
                x->c[q][n] += yr;
                bound[q][n] += rem;
                yr = -yi * fn;
                yi = t * fn;
                rem *= f * r * inv[n + 2];
            }
        }
    }
    for (n = 0; n <= MAX_LOCAL; n++) {
        for (q = 0; q < NX && bound[q][n] <= tol; q++) {}
        if (q == NX) {
            x->degree = n;
            return;
        }
    }
}

/* e, de/dp, k, phi1, phi2 of the contact-line form at phase p: from the local polynomials
 * where there are, else from the series */
static void lines_at(const gd_lines *g, const lexp *x, double p, double v[NQ])
{
    double kin[NX], s = p - x->pm;
    int q, n;
    if (x->degree < 0) {
        gd_lines_eval(g, p, v);
        return;
    }
    for (q = 0; q < NX; q++) {
        double acc = x->c[q][x->degree];
        for (n = x->degree - 1; n >= 0; n--) acc = acc * s + x->c[q][n];
        kin[q] = acc;
    }
    overlap(g, kin, kin[GD_NKIN], p, v);
}

static void tcoef(const tctx *restrict q, double t, double *restrict v)
{
    int d = q->degree, k, j;
    double s;
    const double *c = q->c;
    if (q->lines) {
        lines_at(q->lines, &q->x, q->p0 + q->fm * (t - q->t0), v);
        return;
    }
    s = q->s0 + q->s1 * (t - q->t0);
    /* the five Horner sums side by side: independent chains, not one after another */
    for (k = 0; k < NQ; k++) v[k] = c[k * (d + 1)];
    for (j = 1; j <= d; j++)
        for (k = 0; k < NQ; k++) v[k] = v[k] * s + c[k * (d + 1) + j];
}

static double force(const tctx *restrict q, const double *restrict v, const double *restrict y)
{
    const gd_model *m = q->m;
    return v[2] * (m->rb1 * y[0] - m->rb2 * y[1] + v[0])
        + q->cd * (m->rb1 * y[2] - m->rb2 * y[3] + q->fm * v[1]);
}

static void trhs(const tctx *restrict q, double t, const double *restrict y,
                 double *restrict dy)
{
    const gd_model *m = q->m;
    double v[NQ], f, n;
    tcoef(q, t, v);
    f = force(q, v, y);
    n = f > 0.0 ? f : 0.0;
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = (q->t1 - m->rb1 * f + n * v[3]) * q->inv1;
    dy[3] = (m->rb2 * f - q->t2 + n * v[4]) * q->inv2;
}


/* the outputs a run fills while it steps (gd_tors_run): times t[n], states y[n][4], the table's
 * values coef[n][5] (or NULL), the next one i */
typedef struct {
    long n, i;
    const double *t;
    double *y, *coef;
} sink;

/* the outputs in (t_a, t_b] of the step from y (size h, stages k, end state yn) into o: yn at
 * t_b, elsewhere the continuous extension of order 4 (Hairer, Norsett & Wanner 1993, II.6) */
static void emit(const tctx *q, sink *o, double t_a, double t_b, double h, const double *y,
                 const double *yn, double k[7][4])
{
    double rc[5][4];
    int j, st, ready = 0;
    for (; o->i < o->n && o->t[o->i] <= t_b; o->i++) {
        double *out = o->y + 4 * o->i, th = (o->t[o->i] - t_a) / h;
        if (o->t[o->i] == t_b || th >= 1.0) {
            memcpy(out, yn, 4 * sizeof *out);
        } else {
            if (!ready) {
                for (j = 0; j < 4; j++) {
                    double dd = 0.0;
                    for (st = 0; st < 7; st++) dd += gd_dp_dense[st] * k[st][j];
                    rc[0][j] = y[j];
                    rc[1][j] = yn[j] - y[j];
                    rc[2][j] = h * k[0][j] - rc[1][j];
                    rc[3][j] = rc[1][j] - h * k[6][j] - rc[2][j];
                    rc[4][j] = h * dd;
                }
                ready = 1;
            }
            th = fmax(th, 0.0);
            for (j = 0; j < 4; j++)
                out[j] = rc[0][j] + th * (rc[1][j] + (1.0 - th) * (rc[2][j] + th * (rc[3][j]
                         + (1.0 - th) * rc[4][j])));
        }
        if (o->coef) tcoef(q, o->t[o->i], o->coef + 5 * o->i);
    }
}

/* advance y over dt (s) on one piece; s->h carries the step size from one call to the next;
 * with o, the outputs inside the steps from their dense output (o NULL: the FMU's steps, the
 * last one cut at the communication point) */
static int rk_piece(const tctx *q, gd_state *s, double *y, double dt, sink *o)
{
    const double *sc = q->m->tors->q_scale;
    double tol = s->par[GD_TOL], t = 0.0, h = s->h, k[7][4], yt[4];
    int st, j, l;
    long steps = 0;
    trhs(q, q->t0, y, k[0]);
    while (t < dt) {
        double err = 0.0;
        int last = 0;
        if (++steps > 10000000L) return GD_ERR_STEP;
        if (!(h > 0.0) || h >= dt - t) { h = dt - t; last = 1; }
        for (st = 1; st < 7; st++) {
            for (j = 0; j < 4; j++) {
                double acc = y[j];
                for (l = 0; l < st; l++) acc += h * gd_dp_a[st][l] * k[l][j];
                yt[j] = acc;
            }
            trhs(q, q->t0 + t + gd_dp_c[st] * h, yt, k[st]);
        }
        for (j = 0; j < 4; j++) {
            double e = 0.0, w = tol * (sc[j] + fmax(fabs(y[j]), fabs(yt[j])));
            for (st = 0; st < 7; st++) e += gd_dp_err[st] * k[st][j];
            err += (h * e / w) * (h * e / w) / 4.0;
        }
        err = sqrt(err);
        if (!(err == err) || (!last && h < 1e-15 * (fabs(q->t0) + dt))) return GD_ERR_STEP;
        if (err > 1.0) {
            h *= fmax(0.2, 0.9 * pow(err, -0.2));
            continue;
        }
        if (o) emit(q, o, q->t0 + t, last ? q->t1_end : q->t0 + t + h, h, y, yt, k);
        t = last ? dt : t + h;
        memcpy(y, yt, sizeof yt);
        memcpy(k[0], k[6], sizeof k[0]);
        h *= fmin(5.0, fmax(0.2, 0.9 * pow(fmax(err, 1e-10), -0.2)));
        if (!last || h > s->h) s->h = h;   /* a step cut short by dt keeps the longer one */
        h = s->h;
    }
    return GD_OK;
}

static void setup(tctx *q, const gd_state *s, const gd_model *m)
{
    const gd_tors *g = m->tors;
    double w = s->par[GD_TORQUE] / (m->rb1 - g->arm[0]);
    q->m = m;
    q->c = g->lines ? m->coef : m->coef + (long)s->piece * NQ * (m->degree + 1);
    q->a = m->breaks[s->piece];
    q->b = m->breaks[s->piece + 1];
    q->t0 = s->t;
    q->p0 = s->frac;
    q->fm = m->z1 * s->par[GD_SPEED] / (2.0 * PI);
    q->cd = 2.0 * s->par[GD_ZETA] * sqrt(m->mass * m->k_mean);
    q->t1 = s->par[GD_TORQUE];
    q->t2 = g->load_fixed >= 0.0 ? g->load_fixed : w * (m->rb2 + g->arm[1]);
    q->x.degree = -1;
    q->s0 = (2.0 * q->p0 - q->a - q->b) / (q->b - q->a);
    q->s1 = 2.0 * q->fm / (q->b - q->a);
    q->inv1 = 1.0 / g->inertia[0];
    q->inv2 = 1.0 / g->inertia[1];
    q->degree = m->degree;
    q->lines = g->lines;
}

/* static deflection with delta' = 0 and no rigid-body momentum (TorsionalModel.initial_state) */
void gd_tors_start(gd_state *s, const gd_model *m, double t0)
{
    const gd_tors *g = m->tors;
    double v[NQ], i1 = g->inertia[0], i2 = g->inertia[1], rb1 = m->rb1, rb2 = m->rb2, ed;
    tctx q;
    s->t = t0;
    s->frac = 0.0;
    s->piece = 0;
    setup(&q, s, m);
    tcoef(&q, t0, v);
    ed = q.fm * v[1];
    s->q[0] = 0.0;
    s->q[1] = (v[0] - s->par[GD_TORQUE] / (rb1 - g->arm[0]) / m->k_mean) / rb2;
    s->q[2] = -ed * i2 * rb1 / (i2 * rb1 * rb1 + i1 * rb2 * rb2);
    s->q[3] = -i1 * s->q[2] * rb2 / (i2 * rb1);
    s->h = 2.0 * PI * sqrt(m->mass / m->k_mean) / 64.0;
    s->regime = 1;
    s->n_events = 0;
}

int gd_tors_advance(gd_state *s, const gd_model *m, double t_end)
{
    while (s->t < t_end) {
        tctx q;
        double dt = t_end - s->t, to_edge;
        int hit = 0, rc;
        setup(&q, s, m);
        to_edge = (q.b - s->frac) / q.fm;
        if (to_edge <= dt) { dt = to_edge; hit = 1; }
        else if ((to_edge - dt) * q.fm < 1e-12) hit = 1;   /* an edge at t_end: take it */
        if (m->tors->lines)   /* the phases this stretch steps over: [p0, p0 + f_m dt] */
            lines_expand(m->tors->lines, q.p0 + 0.5 * q.fm * dt, 0.5 * fabs(q.fm * dt),
                         GD_LOCAL_ERROR * m->x_scale, &q.x);
        rc = rk_piece(&q, s, s->q, dt, 0);
        if (rc != GD_OK) return rc;
        if (hit) {
            s->t = dt == t_end - s->t ? t_end : s->t + dt;
            s->frac = m->breaks[++s->piece];
            if (s->piece == m->n_pieces) {
                s->piece = 0;
                s->frac = 0.0;
            }
        } else {
            s->t = t_end;
            s->frac = fmin(s->frac + q.fm * dt, q.b);
        }
    }
    return GD_OK;
}

void gd_tors_coef(const gd_state *s, const gd_model *m, double v[NQ])
{
    tctx q;
    setup(&q, s, m);
    tcoef(&q, s->t, v);
}

void gd_tors_outputs(const gd_state *s, const gd_model *m, double *out)
{
    double v[NQ], f, n;
    const double *y = s->q;
    tctx q;
    setup(&q, s, m);
    tcoef(&q, s->t, v);
    f = force(&q, v, y);
    n = f > 0.0 ? f : 0.0;
    out[GT_Q1] = y[0];
    out[GT_Q2] = y[1];
    out[GT_V1] = y[2];
    out[GT_V2] = y[3];
    out[GT_DTE] = m->rb1 * y[0] - m->rb2 * y[1];
    out[GT_DELTA] = out[GT_DTE] + v[0];
    out[GT_FORCE] = f;
    out[GT_K] = v[2];
    out[GT_W1] = s->par[GD_SPEED] + y[2];
    out[GT_W2] = s->par[GD_SPEED] * m->z1 / m->tors->z2 + y[3];
    out[GT_ECC] = v[0];
    out[GT_TF1] = n * v[3];
    out[GT_TF2] = n * v[4];
}

long gd_tors_run(gd_state *s, const gd_model *m, long n, const double *t, double *y,
                 double *coef, int *status)
{
    /* the mesh phase runs with the time, p0 + f_m (t - t0) (the speed is constant over a run):
     * each piece's end time comes from its edge's phase, cycles + b (cycles: the table's
     * periods passed), not from sums of the steps, which drift by rounding */
    double t0 = s->t, p0 = s->frac, cycles = 0.0, period = m->breaks[m->n_pieces];
    sink o;
    int j;
    o.n = n;
    o.i = 0;
    o.t = t;
    o.y = y;
    o.coef = coef;
    *status = GD_OK;
    while (o.i < n) {
        tctx q;
        double t_edge, t_stop;
        int hit = 1, rc;
        long first = o.i;
        setup(&q, s, m);
        t_edge = t0 + (cycles + q.b - p0) / q.fm;
        t_stop = t_edge;
        if (t[n - 1] < t_edge && (t_edge - t[n - 1]) * q.fm >= 1e-12) {
            t_stop = t[n - 1];   /* the run ends inside this piece */
            hit = 0;
        }
        for (; o.i < n && t[o.i] <= s->t; o.i++) {   /* outputs at the stretch's start */
            memcpy(y + 4 * o.i, s->q, 4 * sizeof *y);
            if (coef) tcoef(&q, t[o.i], coef + 5 * o.i);
        }
        if (o.i < n && t_stop > s->t) {
            double dt = t_stop - s->t;
            q.t1_end = t_stop;
            if (m->tors->lines)
                lines_expand(m->tors->lines, q.p0 + 0.5 * q.fm * dt, 0.5 * fabs(q.fm * dt),
                             GD_LOCAL_ERROR * m->x_scale, &q.x);
            rc = rk_piece(&q, s, s->q, dt, &o);
            if (rc != GD_OK) {
                *status = rc;
                return o.i;
            }
        }
        for (; first < o.i; first++) {
            for (j = 0; j < 4; j++) {
                if (!isfinite(y[4 * first + j])) {
                    *status = GD_ERR_STEP;
                    return first;
                }
            }
        }
        s->t = t_stop;
        if (hit) {
            s->frac = m->breaks[++s->piece];
            if (s->piece == m->n_pieces) {
                s->piece = 0;
                s->frac = 0.0;
                cycles += period;
            }
        } else {
            s->frac = fmin(fmax(p0 + q.fm * (t_stop - t0) - cycles, q.a), q.b);
        }
    }
    return n;
}
