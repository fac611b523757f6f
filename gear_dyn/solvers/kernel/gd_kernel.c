/* gear_dyn native FMU kernel (see gd_kernel.h). Pieces with constant coefficients are propagated
 * in closed form (2x2 linear system, exact solution); the others by the Dormand-Prince 5(4) pair
 * with error control and its 4th-order dense output (Hairer, Norsett & Wanner 1993). Piece
 * boundaries are time events; backlash contact changes are located by root finding (Illinois
 * method) on the closed form or the dense output. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "gd_kernel.h"

#define PI 3.14159265358979323846
#define MAX_EVENTS 100000L

typedef struct {                 /* one piece at constant inputs */
    const gd_model *m;
    int i, regime;
    double t0, frac0, fm, c, w, b;
} ctx;

static void coeffs(const ctx *q, double t, double out[3])
{
    const gd_model *m = q->m;
    double a = m->breaks[q->i], bb = m->breaks[q->i + 1];
    double p = q->frac0 + q->fm * (t - q->t0);
    double s = (2.0 * p - a - bb) / (bb - a);
    int d = m->degree, k, j;
    const double *c = m->coef + (long)q->i * 3 * (d + 1);
    for (k = 0; k < 3; k++, c += d + 1) {
        double acc = c[0];
        for (j = 1; j <= d; j++) acc = acc * s + c[j];
        out[k] = acc;
    }
}

static double spring(const ctx *q, double u)   /* f(u) in the current contact regime */
{
    if (!q->m->has_backlash) return u;
    return q->regime == 1 ? u - q->b : (q->regime == -1 ? u + q->b : 0.0);
}

static void rhs(const ctx *q, double t, const double *y, double *dy)
{
    double k[3];
    coeffs(q, t, k);
    dy[0] = y[1];
    dy[1] = (q->w - q->c * (y[1] - q->fm * k[2]) - k[0] * spring(q, y[0] - k[1])) / q->m->mass;
}

static double gfun(const ctx *q, double t, const double *y)  /* < 0: the regime has ended */
{
    double k[3], u;
    coeffs(q, t, k);
    u = y[0] - k[1];
    if (q->regime == 1) return u - q->b;
    if (q->regime == -1) return -(u + q->b);
    return fmin(q->b - u, u + q->b);
}

static int next_regime(const ctx *q, double t, const double *y)
{
    double k[3];
    if (q->regime != 0) return 0;
    coeffs(q, t, k);
    return y[0] - k[1] > 0.0 ? 1 : -1;
}

/* closed form over time dt of m x'' + c x' + kr (x - xs) = w on a flat piece */
static void exact(const ctx *q, double kr, double xs, const double *y0, double dt, double *y)
{
    double m = q->m->mass, c = q->c;
    if (kr > 0.0) {
        double xe = xs + q->w / kr, X = y0[0] - xe, V = y0[1];
        double tau = -c / (2.0 * m), d2 = tau * tau - kr / m, z = d2 * dt * dt, E, C, S;
        if (fabs(z) < 1e-6) {
            E = exp(tau * dt);
            C = E * (1.0 + z / 2.0 + z * z / 24.0);
            S = E * dt * (1.0 + z / 6.0 + z * z / 120.0);
        } else if (d2 > 0.0) {
            double dl = sqrt(d2), ep = exp((tau + dl) * dt), em = exp((tau - dl) * dt);
            C = 0.5 * (ep + em);
            S = 0.5 * (ep - em) / dl;
        } else {
            double om = sqrt(-d2);
            E = exp(tau * dt);
            C = E * cos(om * dt);
            S = E * sin(om * dt) / om;
        }
        y[0] = xe + C * X + S * (V - tau * X);
        y[1] = C * V + S * (tau * V - kr / m * X);
    } else if (c > 0.0) {                       /* free flight through the gap */
        double a = c / m, vi = q->w / c;
        y[1] = vi + (y0[1] - vi) * exp(-a * dt);
        y[0] = y0[0] + vi * dt - (y0[1] - vi) * expm1(-a * dt) / a;
    } else {
        y[1] = y0[1] + q->w / m * dt;
        y[0] = y0[0] + y0[1] * dt + 0.5 * q->w / m * dt * dt;
    }
}

static void flat_state(const ctx *q, const double *y0, double dt, double *y)
{
    double k[3], kr, xs;
    coeffs(q, q->t0, k);
    kr = k[0];
    xs = k[1];
    if (q->m->has_backlash) {
        if (q->regime == 0) kr = 0.0;
        xs += q->regime * q->b;
    }
    exact(q, kr, xs, y0, dt, y);
}

/* state at local time th of the current step: closed form (flat) or dense output (rc != 0) */
static void state_at(const ctx *q, const double *y0, double (*rc)[2], double h, double th,
                     double *y)
{
    int j;
    if (!rc) {
        flat_state(q, y0, th, y);
        return;
    }
    for (j = 0; j < 2; j++) {
        double s = th / h, s1 = 1.0 - s;
        y[j] = rc[0][j] + s * (rc[1][j] + s1 * (rc[2][j] + s * (rc[3][j] + s1 * rc[4][j])));
    }
}

/* first root of gfun in (ta, tb] (gfun(tb) < 0), Illinois method; t0 is the step start */
static double locate(const ctx *q, const double *y0, double (*rc)[2], double h,
                     double ta, double tb)
{
    double y[2], fa, fb, tm, fm;
    int side = 0, it;
    state_at(q, y0, rc, h, ta, y);
    fa = fabs(gfun(q, q->t0 + ta, y));     /* the start is inside the regime */
    state_at(q, y0, rc, h, tb, y);
    fb = gfun(q, q->t0 + tb, y);
    for (it = 0; it < 200 && tb - ta > 4e-16 * (fabs(q->t0) + tb); it++) {
        tm = (fa - fb > 0.0) ? tb - fb * (tb - ta) / (fb - fa) : 0.5 * (ta + tb);
        if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
        state_at(q, y0, rc, h, tm, y);
        fm = gfun(q, q->t0 + tm, y);
        if (fm < 0.0) {
            tb = tm; fb = fm;
            if (side == -1) fa *= 0.5;
            side = -1;
        } else {
            ta = tm; fa = fm;
            if (side == 1) fb *= 0.5;
            side = 1;
        }
    }
    return tb;
}

/* flat piece: closed form, sampled every 1/32 natural period for contact changes */
static double flat_advance(ctx *q, double *y, double dt, int *event)
{
    double y0[2] = {y[0], y[1]}, yb[2], hs, ta = 0.0;
    long n, j;
    if (!q->m->has_backlash) {
        flat_state(q, y0, dt, y);
        return dt;
    }
    hs = 2.0 * PI * sqrt(q->m->mass / q->m->k_mean) / 32.0;
    n = (long)ceil(dt / hs);
    if (n < 1) n = 1;
    for (j = 1; j <= n; j++) {
        double tb = j == n ? dt : dt * (double)j / (double)n;
        flat_state(q, y0, tb, yb);
        if (gfun(q, q->t0 + tb, yb) < 0.0) {
            double te = locate(q, y0, 0, 0.0, ta, tb);
            flat_state(q, y0, te, y);
            *event = 1;
            return te;
        }
        ta = tb;
    }
    y[0] = yb[0];
    y[1] = yb[1];
    return dt;
}

/* Dormand-Prince 5(4): nodes, stages and the error weights (5th minus 4th order); the torsional
   kernel (gd_torsional.c) steps with the same pair */
const double gd_dp_a[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5, 0, 0, 0, 0, 0},
    {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
    {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
const double gd_dp_c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
const double gd_dp_err[7] = {71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200,
                             22.0 / 525, -1.0 / 40};
const double gd_dp_dense[7] = {-12715105075.0 / 11282082432.0, 0, 87487479700.0 / 32700410799.0,
                                -10690763975.0 / 1880347072.0,
                                701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                69997945.0 / 29380423.0};

static int rk_advance(ctx *q, gd_state *s, double *y, double dt, double *done, int *event)
{
    const gd_model *m = q->m;
    double tol = s->par[GD_TOL], sc[2], t = 0.0, h = s->h, k[7][2], yn[2], yt[2], rc[5][2];
    int st, j, l, steps = 0;
    sc[0] = m->x_scale;
    sc[1] = m->x_scale * sqrt(m->k_mean / m->mass);
    rhs(q, q->t0, y, k[0]);
    while (t < dt) {
        double err = 0.0;
        int last = 0;
        if (++steps > 10000000) return GD_ERR_STEP;
        if (!(h > 0.0) || h >= dt - t) { h = dt - t; last = 1; }
        for (st = 1; st < 7; st++) {
            for (j = 0; j < 2; j++) {
                double acc = y[j];
                for (l = 0; l < st; l++) acc += h * gd_dp_a[st][l] * k[l][j];
                yt[j] = acc;
            }
            rhs(q, q->t0 + t + gd_dp_c[st] * h, yt, k[st]);
        }
        yn[0] = yt[0];
        yn[1] = yt[1];
        for (j = 0; j < 2; j++) {
            double e = 0.0, w = tol * (sc[j] + fmax(fabs(y[j]), fabs(yn[j])));
            for (st = 0; st < 7; st++) e += gd_dp_err[st] * k[st][j];
            err += (h * e / w) * (h * e / w) / 2.0;
        }
        err = sqrt(err);
        if (!(err == err) || (!last && h < 1e-15 * (fabs(q->t0) + dt))) return GD_ERR_STEP;
        if (err > 1.0) {
            h *= fmax(0.2, 0.9 * pow(err, -0.2));
            continue;
        }
        if (m->has_backlash) {
            double y4[2];
            for (j = 0; j < 2; j++) {
                double dd = 0.0;
                for (st = 0; st < 7; st++) dd += gd_dp_dense[st] * k[st][j];
                rc[0][j] = y[j];
                rc[1][j] = yn[j] - y[j];
                rc[2][j] = h * k[0][j] - rc[1][j];
                rc[3][j] = rc[1][j] - h * k[6][j] - rc[2][j];
                rc[4][j] = h * dd;
            }
            for (st = 1; st <= 4; st++) {       /* dense samples at h/4 .. h */
                double tb = h * st / 4.0, t0 = q->t0, frac0 = q->frac0;
                q->t0 += t;                     /* time origin at the step start: the */
                q->frac0 += q->fm * t;          /* mesh phase moves with it */
                state_at(q, y, rc, h, tb, y4);
                if (gfun(q, q->t0 + tb, y4) < 0.0) {
                    double te = locate(q, y, rc, h, h * (st - 1) / 4.0, tb);
                    state_at(q, y, rc, h, te, y);
                    q->t0 = t0;
                    q->frac0 = frac0;
                    *done = t + te;
                    *event = 1;
                    s->h = h;
                    return GD_OK;
                }
                q->t0 = t0;
                q->frac0 = frac0;
            }
        }
        t = last ? dt : t + h;
        y[0] = yn[0];
        y[1] = yn[1];
        memcpy(k[0], k[6], sizeof k[0]);
        h *= fmin(5.0, fmax(0.2, 0.9 * pow(fmax(err, 1e-10), -0.2)));
        if (!last || h > s->h) s->h = h;
        h = s->h;
    }
    *done = dt;
    return GD_OK;
}

void gd_defaults(gd_state *s, const gd_model *m)
{
    memset(s, 0, sizeof *s);
    memcpy(s->par, m->start, sizeof s->par);
}

static void locate_piece(gd_state *s, const gd_model *m)
{
    int i = 0;
    while (i < m->n_pieces - 1 && m->breaks[i + 1] <= s->frac) i++;
    s->piece = i;
}

void gd_start(gd_state *s, const gd_model *m, double t0)
{
    double fm = m->z1 * s->par[GD_SPEED] / (2.0 * PI), k[3];
    double b = m->has_backlash ? s->par[GD_HALF_GAP] : 0.0;
    ctx q;
    if (m->tors) {
        gd_tors_start(s, m, t0);
        return;
    }
    s->t = t0;
    s->frac = m->phase0 - floor(m->phase0);
    locate_piece(s, m);
    q.m = m; q.i = s->piece; q.t0 = t0; q.frac0 = s->frac; q.fm = fm;
    coeffs(&q, t0, k);
    s->x = s->par[GD_TORQUE] / m->rb1 / m->k_mean + b + k[1];
    s->v = fm * k[2];
    s->regime = 1;
    s->h = 2.0 * PI * sqrt(m->mass / m->k_mean) / 64.0;
    s->n_events = 0;
}

int gd_advance(gd_state *s, const gd_model *m, double t_end)
{
    ctx q;
    if (m->tors) return gd_tors_advance(s, m, t_end);
    q.m = m;
    q.fm = m->z1 * s->par[GD_SPEED] / (2.0 * PI);
    q.c = 2.0 * s->par[GD_ZETA] * sqrt(m->mass * m->k_mean);
    q.w = s->par[GD_TORQUE] / m->rb1;
    q.b = m->has_backlash ? s->par[GD_HALF_GAP] : 0.0;
    while (s->t < t_end) {
        double y[2] = {s->x, s->v}, dt = t_end - s->t, done = 0.0;
        double to_edge = (m->breaks[s->piece + 1] - s->frac) / q.fm;
        int hit = 0, event = 0, rc = GD_OK;
        if (to_edge <= dt) { dt = to_edge; hit = 1; }
        else if ((to_edge - dt) * q.fm < 1e-12) hit = 1;   /* a switch at t_end: take it */
        q.i = s->piece; q.regime = s->regime; q.t0 = s->t; q.frac0 = s->frac;
        if (m->flat[s->piece]) done = flat_advance(&q, y, dt, &event);
        else rc = rk_advance(&q, s, y, dt, &done, &event);
        if (rc != GD_OK) return rc;
        s->x = y[0];
        s->v = y[1];
        if (event) {
            s->t += done;
            s->frac += q.fm * done;
            s->regime = next_regime(&q, s->t, y);
            if (++s->n_events > MAX_EVENTS) return GD_ERR_STEP;
        } else if (hit) {
            s->t = dt == t_end - s->t ? t_end : s->t + dt;
            s->frac = m->breaks[++s->piece];
            if (s->piece == m->n_pieces) { s->piece = 0; s->frac = 0.0; }
        } else {
            s->t = t_end;
            s->frac += q.fm * dt;
        }
        if (s->frac >= m->breaks[s->piece + 1]) s->frac = m->breaks[s->piece + 1];
    }
    return GD_OK;
}

void gd_outputs(const gd_state *s, const gd_model *m, double *out)
{
    double k[3], u, ud, f;
    double fm = m->z1 * s->par[GD_SPEED] / (2.0 * PI), b = s->par[GD_HALF_GAP];
    ctx q;
    if (m->tors) {
        gd_tors_outputs(s, m, out);
        return;
    }
    q.m = m; q.i = s->piece; q.t0 = s->t; q.frac0 = s->frac; q.fm = fm;
    coeffs(&q, s->t, k);
    u = s->x - k[1];
    ud = s->v - fm * k[2];
    f = !m->has_backlash ? u : (u > b ? u - b : (u < -b ? u + b : 0.0));
    out[GD_X] = out[GD_DTE] = s->x;
    out[GD_V] = s->v;
    out[GD_FORCE] = k[0] * f + 2.0 * s->par[GD_ZETA] * sqrt(m->mass * m->k_mean) * ud;
    out[GD_K] = k[0];
    out[GD_DRIVEN] = (m->rb1 * s->par[GD_SPEED] - s->v) / m->rb2;
}

int gd_get(const gd_state *s, const gd_model *m, const unsigned *vr, size_t n, double *v)
{
    double out[GD_MAX_OUT];
    unsigned n_out = m->tors ? GT_NOUT : GD_NOUT;
    size_t k;
    gd_outputs(s, m, out);
    for (k = 0; k < n; k++) {
        if (vr[k] == 0) v[k] = s->t;   /* FMI 3's independent variable */
        else if (vr[k] <= GD_NPAR) v[k] = s->par[vr[k] - 1];
        else if (vr[k] > GD_NPAR && vr[k] <= GD_NPAR + n_out) v[k] = out[vr[k] - GD_NPAR - 1];
        else return GD_ERR_VR;
    }
    return GD_OK;
}

/* the shortest of %.15g, %.17g that reads back as v */
static const char *num(char *buf, double v)
{
    sprintf(buf, "%.15g", v);
    if (strtod(buf, NULL) != v) sprintf(buf, "%.17g", v);
    return buf;
}

int gd_set(gd_state *s, const gd_model *m, unsigned vr, double value, int started, char *msg,
           size_t len)
{
    int j = (int)vr - 1;
    const gd_param *p;
    const char *u;
    char a[32], b[32], c[32];
    if (j < 0 || j >= GD_NPAR || (j == GD_HALF_GAP && !m->has_backlash)) {
        snprintf(msg, len, "value reference %u: not a parameter or input of this FMU", vr);
        return GD_ERR_VR;
    }
    p = &m->params[j];
    if (started && j > GD_TORQUE) {
        snprintf(msg, len, "%s is a fixed parameter: set it before initialization "
                 "(or reset the instance)", p->name);
        return GD_ERR_VR;
    }
    if (!(value == value) || value > p->high || value < p->low
        || (p->low_open && value == p->low)) {
        u = strcmp(p->unit, "1") ? p->unit : "";
        snprintf(msg, len, "%s = %s%s%s is out of range: valid range %s%s, %s]%s%s", p->name,
                 num(a, value), *u ? " " : "", u, p->low_open ? "(" : "[", num(b, p->low),
                 num(c, p->high), *u ? " " : "", u);
        return GD_ERR_RANGE;
    }
    s->par[j] = value;
    return GD_OK;
}
