/* The drivetrain interface (gd_drive.h): the two-DOF torsional mesh between two shafts, each
 * driven by a torque input, in absolute angles y = [th1, th2, w1, w2]:
 *
 *   I1 w1' = T1 - r_b1 F + max(F, 0) phi1(p),   I2 w2' = T2 + r_b2 F + max(F, 0) phi2(p)
 *   F = k(p) f(u + s e(p)) + c (u' + s f_m de/dp),   u = r_b1 th1 - r_b2 th2,
 *   p = p_0 + z1 th1 / (2 pi),  f_m = z1 w1 / (2 pi),  c = 2 xi sqrt(m_e k_m),
 *   m_e = I1 I2 / (I1 r_b2^2 + I2 r_b1^2)
 *
 * T1, T2 act on the shafts in their positive sense of rotation (a load is a negative T2). In
 * the speed-driven variant (speed_in) the pinion turns at its input speed w1 (held over a step)
 * and the output in w1's place is the torque its shaft delivers, r_b1 F - max(F, 0) phi1. The
 * mesh phase follows the pinion angle, so the table's piece edges are reached when th1 reaches
 * them: each Runge-Kutta step (Dormand-Prince 5(4) with error control, Hairer, Norsett & Wanner
 * 1993; absolute error weights: the angles grow without bound) that would cross an edge is
 * shortened by the secant method until it ends on the edge.
 * f is the identity, or the backlash dead zone of half gap b (continuous: its kinks are left to
 * the error control). s = -1 for the single-DOF tables (e: the transmission error), +1 for the
 * torsional ones (e: the eccentric kinematic error). An eccentric pair's contact-line form has
 * no polynomials: e, de/dp, k, phi1, phi2 come from its series (gd_lines_eval, gd_torsional.c),
 * the pieces remaining as the edges the steps end on. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "gd_drive.h"

#define PI 3.14159265358979323846

typedef struct {
    const gd_model *m;
    const gd_drive *d;
    const double *c;            /* the piece's coefficients */
    double a, b;                /* its phase edges */
    double p0, th0;             /* phase and pinion angle at the step start */
    const double *par;
    double cd;
} dctx;

static void dcoef(const dctx *q, double th1, double v[5])
{
    int deg = q->m->degree, k, j;
    double p = q->p0 + q->m->z1 * (th1 - q->th0) / (2.0 * PI);
    double s = (2.0 * p - q->a - q->b) / (q->b - q->a);
    if (q->m->tors && q->m->tors->lines) {   /* the contact-line form: no polynomials */
        gd_lines_eval(q->m->tors->lines, p, v);
        return;
    }
    for (k = 0; k < 5; k++) {
        double acc = 0.0;
        if (q->d->idx[k] >= 0) {
            const double *c = q->c + q->d->idx[k] * (deg + 1);
            for (acc = c[0], j = 1; j <= deg; j++) acc = acc * s + c[j];
        }
        v[k] = acc;
    }
}

static double force(const dctx *q, const double *v, const double *y)
{
    const gd_model *m = q->m;
    double u = m->rb1 * y[0] - m->rb2 * y[1] + q->d->sign_e * v[0], b = q->par[GV_HALF_GAP];
    double el = !m->has_backlash ? u : (u > b ? u - b : (u < -b ? u + b : 0.0));
    double fm = m->z1 * y[2] / (2.0 * PI);
    return v[2] * el + q->cd * (m->rb1 * y[2] - m->rb2 * y[3] + q->d->sign_e * fm * v[1]);
}

static void drhs(const dctx *q, const double *y, double *dy)
{
    double v[5], f, n;
    dcoef(q, y[0], v);
    f = force(q, v, y);
    n = f > 0.0 ? f : 0.0;
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = q->d->speed_in ? 0.0 : (q->par[GV_T1] - q->m->rb1 * f + n * v[3]) / q->par[GV_I1];
    dy[3] = (q->par[GV_T2] + q->m->rb2 * f + n * v[4]) / q->par[GV_I2];
}

static double phase(const dctx *q, double th1)
{
    return q->p0 + q->m->z1 * (th1 - q->th0) / (2.0 * PI);
}

static double mass(const gd_model *m, const double *par)
{
    double i1 = par[GV_I1], i2 = par[GV_I2];
    return i1 * i2 / (i1 * m->rb2 * m->rb2 + i2 * m->rb1 * m->rb1);
}

static void setup(dctx *q, const gd_dstate *s, const gd_model *m, const gd_drive *d)
{
    q->m = m;
    q->d = d;
    q->c = m->tors && m->tors->lines ? m->coef
        : m->coef + (long)s->k.piece * d->nq * (m->degree + 1);
    q->a = m->breaks[s->k.piece];
    q->b = m->breaks[s->k.piece + 1];
    q->p0 = s->k.frac;
    q->th0 = s->k.q[0];
    q->par = s->par;
    q->cd = 2.0 * s->par[GV_ZETA] * sqrt(mass(m, s->par) * m->k_mean);
}

/* one Dormand-Prince step of h from y into yn; its error norm */
static double dp_step(const dctx *q, const double *sc, double tol, const double *y,
                      const double *k0, double h, double k[7][4], double *yn)
{
    double err = 0.0;
    int st, j, l;
    memcpy(k[0], k0, sizeof k[0]);
    for (st = 1; st < 7; st++) {
        for (j = 0; j < 4; j++) {
            double acc = y[j];
            for (l = 0; l < st; l++) acc += h * gd_dp_a[st][l] * k[l][j];
            yn[j] = acc;
        }
        drhs(q, yn, k[st]);
    }
    for (j = 0; j < 4; j++) {
        double e = 0.0, w = tol * sc[j];   /* absolute: the angles grow without bound */
        for (st = 0; st < 7; st++) e += gd_dp_err[st] * k[st][j];
        err += (h * e / w) * (h * e / w) / 4.0;
    }
    return sqrt(err);
}

/* advance over at most dt on the current piece; *done: time taken, *edge: +1/-1 if it ended
 * on the upper/lower piece edge */
static int rk_piece(const dctx *q, gd_dstate *s, double dt, double *done, int *edge)
{
    const double *sc = q->d->q_scale;
    double tol = s->par[GV_TOL], t = 0.0, h = s->k.h, k[7][4], k0[4], yn[4], *y = s->k.q;
    double span = q->b - q->a;
    long steps = 0;
    *edge = 0;
    drhs(q, y, k0);
    while (t < dt) {
        double err, p;
        int last = 0, it;
        if (++steps > 10000000L) return GD_ERR_STEP;
        if (!(h > 0.0) || h >= dt - t) { h = dt - t; last = 1; }
        err = dp_step(q, sc, tol, y, k0, h, k, yn);
        if (!(err == err) || (!last && h < 1e-15 * (fabs(s->k.t) + dt))) return GD_ERR_STEP;
        if (err > 1.0) {
            h *= fmax(0.2, 0.9 * pow(err, -0.2));
            continue;
        }
        p = phase(q, yn[0]);
        if (p > q->b || p < q->a) {     /* the step leaves the piece: end it on the edge */
            double target = p > q->b ? q->b : q->a, p0 = phase(q, y[0]), hl = 0.0, pl = p0;
            double hh = h, ph = p;
            *edge = p > q->b ? 1 : -1;
            for (it = 0; it < 60; it++) {
                double hn = hl + (hh - hl) * (target - pl) / (ph - pl), pn;
                if (!(hn > hl && hn < hh)) hn = 0.5 * (hl + hh);
                dp_step(q, sc, tol, y, k0, hn, k, yn);
                pn = phase(q, yn[0]);
                if (fabs(pn - target) <= 1e-13 * span || hh - hl <= 1e-15 * fabs(s->k.t)) {
                    h = hn;
                    break;
                }
                if ((pn - target) * (ph - target) > 0.0) { hh = hn; ph = pn; }
                else { hl = hn; pl = pn; }
                h = hn;
            }
            memcpy(y, yn, sizeof yn);
            *done = t + h;
            return GD_OK;
        }
        t = last ? dt : t + h;
        memcpy(y, yn, sizeof yn);
        memcpy(k0, k[6], sizeof k0);
        h *= fmin(5.0, fmax(0.2, 0.9 * pow(fmax(err, 1e-10), -0.2)));
        if (!last || h > s->k.h) s->k.h = h;
        h = s->k.h;
    }
    *done = dt;
    return GD_OK;
}

void gd_drive_defaults(gd_dstate *s, const gd_model *m, const gd_drive *d)
{
    memset(s, 0, sizeof *s);
    memcpy(s->k.par, m->start, sizeof s->k.par);
    memcpy(s->par, d->start, sizeof s->par);
}

static void locate(gd_dstate *s, const gd_model *m)
{
    int i = 0;
    while (i < m->n_pieces - 1 && m->breaks[i + 1] <= s->k.frac) i++;
    s->k.piece = i;
}

/* at rest in the mesh: the static deflection of the pinion torque, both shafts at the start
 * speed's kinematics (u' + s f_m de/dp = 0) */
void gd_drive_start(gd_dstate *s, const gd_model *m, const gd_drive *d, double t0)
{
    double v[5], w1 = s->par[d->speed_in ? GV_T1 : GV_W0], el;
    dctx q;
    s->k.t = t0;
    s->k.frac = fmod(fmod(m->phase0, d->period) + d->period, d->period);
    locate(s, m);
    s->k.q[0] = 0.0;
    setup(&q, s, m, d);
    dcoef(&q, 0.0, v);
    el = (d->speed_in ? -s->par[GV_T2] / m->rb2 : s->par[GV_T1] / m->rb1)
        / (v[2] > 0.0 ? v[2] : m->k_mean);
    if (m->has_backlash) el += (el >= 0.0 ? 1.0 : -1.0) * s->par[GV_HALF_GAP];
    s->k.q[1] = -(el - d->sign_e * v[0]) / m->rb2;
    s->k.q[2] = w1;
    s->k.q[3] = (m->rb1 * w1 + d->sign_e * m->z1 * w1 / (2.0 * PI) * v[1]) / m->rb2;
    s->k.h = 2.0 * PI * sqrt(mass(m, s->par) / m->k_mean) / 64.0;
    s->k.regime = 1;
    s->k.n_events = 0;
}

int gd_drive_advance(gd_dstate *s, const gd_model *m, const gd_drive *d, double t_end)
{
    while (s->k.t < t_end) {
        dctx q;
        double done = 0.0, dt = t_end - s->k.t;
        int edge, rc;
        if (d->speed_in) s->k.q[2] = s->par[GV_T1];   /* the pinion at its input speed */
        setup(&q, s, m, d);
        rc = rk_piece(&q, s, dt, &done, &edge);
        if (rc != GD_OK) return rc;
        s->k.t = done >= dt ? t_end : s->k.t + done;
        if (edge > 0) {
            if (++s->k.piece == m->n_pieces) s->k.piece = 0;
            s->k.frac = m->breaks[s->k.piece];
        } else if (edge < 0) {
            if (--s->k.piece < 0) s->k.piece = m->n_pieces - 1;
            s->k.frac = m->breaks[s->k.piece + 1];
        } else {
            s->k.frac = fmin(fmax(phase(&q, s->k.q[0]), q.a), q.b);
        }
    }
    return GD_OK;
}

int gd_drive_get(const gd_dstate *s, const gd_model *m, const gd_drive *d, const unsigned *vr,
                 size_t n, double *v)
{
    double c[5], out[GV_NOUT], y[4];
    size_t j;
    dctx q;
    memcpy(y, s->k.q, sizeof y);
    if (d->speed_in) y[2] = s->par[GV_T1];   /* the speed input acts at once on the force */
    setup(&q, s, m, d);
    dcoef(&q, y[0], c);
    out[GV_FORCE] = force(&q, c, y);
    out[GV_A1] = y[0];
    out[GV_W1] = !d->speed_in ? y[2]   /* speed_in: the torque the pinion shaft delivers */
        : m->rb1 * out[GV_FORCE] - (out[GV_FORCE] > 0.0 ? out[GV_FORCE] : 0.0) * c[3];
    out[GV_A2] = y[1];
    out[GV_W2] = y[3];
    out[GV_DTE] = m->rb1 * y[0] - m->rb2 * y[1];
    for (j = 0; j < n; j++) {
        if (vr[j] == 0) v[j] = s->k.t;
        else if (vr[j] <= GV_NPAR) v[j] = s->par[vr[j] - 1];
        else if (vr[j] <= GV_NPAR + GV_NOUT) v[j] = out[vr[j] - GV_NPAR - 1];
        else if (vr[j] == GV_NPAR + GV_NOUT + 1) v[j] = m->rb1;   /* calculated parameters */
        else if (vr[j] == GV_NPAR + GV_NOUT + 2) v[j] = m->rb2;
        else if (vr[j] == GV_NPAR + GV_NOUT + 3) v[j] = m->rb2 / m->rb1;
        else return GD_ERR_VR;
    }
    return GD_OK;
}

int gd_drive_set(gd_dstate *s, const gd_drive *d, unsigned vr, double value, int started,
                 char *msg, size_t len)
{
    int j = (int)vr - 1;
    const gd_param *p;
    if (j < 0 || j >= GV_NPAR) {
        snprintf(msg, len, "value reference %u: not a parameter or input of this FMU", vr);
        return GD_ERR_VR;
    }
    p = &d->params[j];
    if (started && j > GV_T2) {
        snprintf(msg, len, "%s is a fixed parameter: set it before initialization "
                 "(or reset the instance)", p->name);
        return GD_ERR_VR;
    }
    if (!(value == value) || value > p->high || value < p->low
        || (p->low_open && value == p->low)) {
        const char *u = strcmp(p->unit, "1") ? p->unit : "";
        snprintf(msg, len, "%s = %.17g%s%s is out of range: valid range %s%.17g, %.17g]%s%s",
                 p->name, value, *u ? " " : "", u, p->low_open ? "(" : "[", p->low, p->high,
                 *u ? " " : "", u);
        return GD_ERR_RANGE;
    }
    s->par[j] = value;
    return GD_OK;
}
