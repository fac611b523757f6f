/* gear_dyn flow kernel (see gd_flow.h): products and applications of affine step maps. The
 * maps themselves (matrix exponentials of the pieces, collocation maps) come from Python; only
 * the sequential part, which numpy would run one small product per Python iteration, is here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "gd_flow.h"

int gd_flow_version(void)
{
    return GD_FLOW_VERSION;
}

double gd_flow_grid_error(long n, const double *t, double t0, double dt)
{
    double worst = 0.0;
    long i;
    for (i = 0; i < n; i++) {
        double d = fabs(t[i] - (t0 + (double)i * dt));
        if (isnan(d)) return d;         /* a NaN time: not uniform */
        if (d > worst) worst = d;
    }
    return worst;
}

/* y = F x + h (y and x distinct) */
static void affine(int n, const double *F, const double *h, const double *x, double *y)
{
    int i, k;
    for (i = 0; i < n; i++) {
        double acc = h ? h[i] : 0.0;
        for (k = 0; k < n; k++) acc += F[i * n + k] * x[k];
        y[i] = acc;
    }
}

void gd_flow_products(int n, long count, const double *F, const double *h, double *Q,
                      double *R)
{
    long j;
    int i, k, l;
    size_t nn = (size_t)n * (size_t)n;
    memset(Q, 0, nn * sizeof(double));
    memset(R, 0, (size_t)n * sizeof(double));
    for (i = 0; i < n; i++) Q[i * n + i] = 1.0;
    for (j = 0; j < count; j++) {
        const double *f = F + (size_t)j * nn, *q = Q + (size_t)j * nn;
        double *qn = Q + (size_t)(j + 1) * nn;
        for (i = 0; i < n; i++)
            for (l = 0; l < n; l++) {
                double acc = 0.0;
                for (k = 0; k < n; k++) acc += f[i * n + k] * q[k * n + l];
                qn[i * n + l] = acc;
            }
        affine(n, f, h + (size_t)j * n, R + (size_t)j * n, R + (size_t)(j + 1) * n);
    }
}

void gd_flow_compose(int n, long n_parts, const double *parts, const long *owner, long n_steps,
                     double *total)
{
    int m = n + 1, i, k, l;
    size_t mm = (size_t)m * (size_t)m;
    long j;
    double tmp[65 * 65];
    if (m > 65) return;
    memset(total, 0, (size_t)n_steps * mm * sizeof(double));
    for (j = 0; j < n_steps; j++)
        for (i = 0; i < m; i++) total[(size_t)j * mm + (size_t)(i * m + i)] = 1.0;
    for (j = 0; j < n_parts; j++) {
        const double *p = parts + (size_t)j * mm;
        double *t = total + (size_t)owner[j] * mm;
        for (i = 0; i < m; i++)
            for (l = 0; l < m; l++) {
                double acc = 0.0;
                for (k = 0; k < m; k++) acc += p[i * m + k] * t[k * m + l];
                tmp[i * m + l] = acc;
            }
        memcpy(t, tmp, mm * sizeof(double));
    }
}

void gd_flow_chain(int n, long count, const double *F, const double *h, const double *y0,
                   double *Y)
{
    long j;
    size_t nn = (size_t)n * (size_t)n;
    memcpy(Y, y0, (size_t)n * sizeof(double));
    for (j = 0; j < count; j++)
        affine(n, F + (size_t)j * nn, h + (size_t)j * n, Y + (size_t)j * n,
               Y + (size_t)(j + 1) * n);
}

/* NaN from sample idx on, in every state */
static int diverged(int n, long idx, long n_samples, double *out)
{
    int i;
    long rest;
    for (i = 0; i < n; i++)
        for (rest = idx; rest < n_samples; rest++)
            out[(size_t)i * (size_t)n_samples + (size_t)rest] = NAN;
    return 1;
}

/* gd_flow_fill_periodic for two states (the single-DOF model), unrolled */
static int fill2(long s_per, long n_samples, const double *Q, const double *R, const double *y0,
                 double *out)
{
    double a = y0[0], b = y0[1], *x = out, *v = out + n_samples;
    long idx = 0, j;
    while (idx < n_samples) {
        for (j = 0; j < s_per && idx < n_samples; j++, idx++) {
            const double *q = Q + 4 * j, *r = R + 2 * j;
            double p0 = q[0] * a + q[1] * b + r[0], p1 = q[2] * a + q[3] * b + r[1];
            if (!(isfinite(p0) && isfinite(p1))) return diverged(2, idx, n_samples, out);
            x[idx] = p0;
            v[idx] = p1;
        }
        if (idx < n_samples) {          /* the next period start from this one */
            const double *q = Q + 4 * s_per, *r = R + 2 * s_per;
            double na = q[0] * a + q[1] * b + r[0];
            b = q[2] * a + q[3] * b + r[1];
            a = na;
        }
    }
    return 0;
}

int gd_flow_fill_periodic(int n, long s_per, long n_samples, const double *Q, const double *R,
                          const double *y0, double *out)
{
    double start[64], next[64], y[64];
    size_t nn = (size_t)n * (size_t)n;
    long idx, j = 0;
    int i;
    if (n < 1 || n > 64 || s_per < 1) return 1;
    if (n == 2) return fill2(s_per, n_samples, Q, R, y0, out);
    memcpy(start, y0, (size_t)n * sizeof(double));
    for (idx = 0; idx < n_samples; idx++, j++) {
        if (j == s_per) {               /* a period start: the next one from this one */
            affine(n, Q + (size_t)s_per * nn, R + (size_t)s_per * n, start, next);
            memcpy(start, next, (size_t)n * sizeof(double));
            j = 0;
        }
        affine(n, Q + (size_t)j * nn, R + (size_t)j * n, start, y);
        for (i = 0; i < n; i++) {
            if (!isfinite(y[i])) return diverged(n, idx, n_samples, out);
            out[(size_t)i * (size_t)n_samples + (size_t)idx] = y[i];
        }
    }
    return 0;
}

/* ---- the contact walk (gd_flow.h; gear_dyn.solvers.contact_exact) ----
 * The same algorithm the Python walk ran, step for step: closed form in each contact state;
 * a contact change bracketed on samples a quarter damped (and top harmonic) period apart and
 * closed by gd_find_root; pieces that provably stay in their state are not searched. */

#define CW_STACK 256            /* bisection depth of a crossing search (~60 is the most used) */

/* The closed form of one contact state (contact_exact.flow), split in its constants (cw_form),
 * the transcendental terms at a time s (cw_terms: what the exponential and trigonometric
 * functions give) and their application to a start state, so the walk evaluates the terms once
 * where it needs several states at the same s (the segment end and the two columns of its
 * sensitivity), and reads the constants from the piece row instead of dividing again. */
typedef struct {
    int state;                  /* -1, 0, 1 */
    int kind;                   /* 1 underdamped, 2 overdamped, 3 critical; in the gap 0 (a = 0)
                                   or 4 */
    double a, w2, x_eq, wm, q;  /* c/m, k/m, state b + w/k, w/m, damped (or decay) frequency */
} cw_form;

typedef struct {
    double s, cs, sn, dec, e1;
} cw_terms;

static cw_form form_of(int state, double k, double m, double c, double w, double b)
{
    cw_form f;
    double q2;
    f.state = state;
    f.a = c / m;
    f.wm = w / m;
    f.w2 = f.x_eq = f.q = 0.0;
    if (state == 0) {
        f.kind = f.a == 0.0 ? 0 : 4;
        return f;
    }
    f.w2 = k / m;
    f.x_eq = state * b + w / k;
    q2 = 0.25 * f.a * f.a - f.w2;
    if (q2 < 0.0) {
        f.kind = 1;
        f.q = sqrt(-q2);
    } else if (q2 > 0.0) {
        f.kind = 2;
        f.q = sqrt(q2);
    } else {
        f.kind = 3;
    }
    return f;
}

static void form_terms(const cw_form *f, double s, cw_terms *e)
{
    e->s = s;
    if (s == 0.0) {             /* the start (each search's first sample): no function calls */
        e->cs = e->dec = 1.0;
        e->sn = e->e1 = 0.0;
        return;
    }
    switch (f->kind) {
    case 1:
        e->cs = cos(f->q * s);
        e->sn = sin(f->q * s) / f->q;
        break;
    case 2:
        e->cs = cosh(f->q * s);
        e->sn = sinh(f->q * s) / f->q;
        break;
    case 3:
        e->cs = 1.0;
        e->sn = s;
        break;
    case 4:
        e->e1 = -expm1(-f->a * s) / f->a;   /* (1 - e^{-a s}) / a, exact also for small a s */
        return;
    default:
        return;
    }
    e->dec = exp(-0.5 * f->a * s);
}

/* x(s), v(s) from (x0, v0); x_eq and wm given apart (the sensitivity's unit starts take the
 * form without load: both zero) */
static void form_apply(const cw_form *f, const cw_terms *e, double x_eq, double wm, double x0,
                       double v0, double *x, double *v)
{
    double a = f->a, s = e->s, u0;
    if (f->kind == 0) {
        *x = x0 + v0 * s + 0.5 * wm * s * s;
        *v = v0 + wm * s;
        return;
    }
    if (f->kind == 4) {
        *x = x0 + v0 * e->e1 + wm * (s - e->e1) / a;
        *v = v0 + (wm - a * v0) * e->e1;
        return;
    }
    u0 = x0 - x_eq;
    *x = x_eq + e->dec * (e->cs * u0 + e->sn * (v0 + 0.5 * a * u0));
    *v = e->dec * (e->cs * v0 - e->sn * (f->w2 * u0 + 0.5 * a * v0));
}

/* x(s), v(s) in one contact state: the closed form of contact_exact.flow */
static void flow1(int state, double k, double m, double c, double w, double b, double x0,
                  double v0, double s, double *x, double *v)
{
    cw_form f = form_of(state, k, m, c, w, b);
    cw_terms e;
    form_terms(&f, s, &e);
    form_apply(&f, &e, f.x_eq, f.wm, x0, v0, x, v);
}

typedef struct {
    double m, c, w, b, fm, p0, wm;   /* wm = w / m */
    long nh;
    const double *tn, *om;
} cw_model;

typedef struct {
    int state;
    double k, a, w2, q, x_eq, h, amp, curv;
    const double *ca, *cb;
    cw_form f;                  /* the closed form's constants, from the row */
} cw_piece;

static cw_model cw_model_of(const double *model)
{
    cw_model md;
    md.m = model[0];
    md.c = model[1];
    md.w = model[2];
    md.b = model[3];
    md.fm = model[4];
    md.p0 = model[5];
    md.wm = md.w / md.m;
    md.nh = (long)model[6];
    md.tn = model + GD_CW_MODEL;
    md.om = model + GD_CW_MODEL + md.nh;
    return md;
}

static cw_piece cw_piece_of(const cw_model *md, const double *pieces, long row)
{
    const double *r = pieces + (size_t)row * (size_t)(GD_CW_ROW + 2 * md->nh);
    cw_piece pc;
    pc.state = (int)r[0];
    pc.k = r[1];
    pc.a = r[2];
    pc.w2 = r[3];
    pc.q = r[4];
    pc.x_eq = r[5];
    pc.h = r[6];
    pc.amp = r[7];
    pc.curv = r[8];
    pc.ca = r + GD_CW_ROW;
    pc.cb = r + GD_CW_ROW + md->nh;
    /* the row holds a = c/m, w2 = k/m, x_eq = state b + w/k and the damped frequency q (0:
     * none) as form_of computes them; the overdamped and critical forms are computed here */
    if (pc.state != 0 && !(pc.q > 0.0)) {
        pc.f = form_of(pc.state, pc.k, md->m, md->c, md->w, md->b);
    } else {
        pc.f.state = pc.state;
        pc.f.kind = pc.state != 0 ? 1 : (pc.a == 0.0 ? 0 : 4);
        pc.f.a = pc.a;
        pc.f.w2 = pc.w2;
        pc.f.x_eq = pc.x_eq;
        pc.f.wm = md->wm;
        pc.f.q = pc.q;
    }
    return pc;
}

void gd_contact_flow(int state, double k, double m, double c, double w, double b, double x0,
                     double v0, long n, const double *s, double *x, double *v)
{
    long i;
    for (i = 0; i < n; i++) flow1(state, k, m, c, w, b, x0, v0, s[i], x + i, v + i);
}

/* u_p(t), u_p'(t) of a piece's particular solution (zero without harmonics) */
static void part_at(const cw_model *md, const cw_piece *pc, double t, double *pu, double *pv)
{
    double p, u = 0.0, v = 0.0;
    long i;
    if (md->nh > 0) {
        p = fmod(md->fm * t + md->p0, 1.0);
        for (i = 0; i < md->nh; i++) {
            double cs = cos(md->tn[i] * p), sn = sin(md->tn[i] * p);
            u += pc->ca[i] * cs + pc->cb[i] * sn;
            v += md->om[i] * (pc->cb[i] * cs - pc->ca[i] * sn);
        }
    }
    *pu = u;
    *pv = v;
}

/* the state of z = u - u_p at t0 */
static void z_of(const cw_model *md, const cw_piece *pc, double u0, double v0, double t0,
                 double *z0, double *zv0)
{
    double pu, pv;
    if (md->nh == 0) {
        *z0 = u0;
        *zv0 = v0;
        return;
    }
    part_at(md, pc, t0, &pu, &pv);
    *z0 = u0 - pu;
    *zv0 = v0 - pv;
}

static void hom(const cw_model *md, const cw_piece *pc, double z0, double zv0, double s,
                double *zx, double *zv)
{
    cw_terms e;
    (void)md;
    form_terms(&pc->f, s, &e);
    form_apply(&pc->f, &e, pc->f.x_eq, pc->f.wm, z0, zv0, zx, zv);
}

/* u, u' at time t from (z0, zv0), the state of z at t0 (s = t - t0) */
static void piece_eval(const cw_model *md, const cw_piece *pc, double z0, double zv0,
                       double s, double t, double *x, double *v)
{
    double pu, pv;
    hom(md, pc, z0, zv0, s, x, v);
    if (md->nh > 0) {
        part_at(md, pc, t, &pu, &pv);
        *x += pu;
        *v += pv;
    }
}

static int stays_inside(const cw_model *md, const cw_piece *pc, double u0, double v0,
                        double t0)
{
    double z0, zv0, u, amp;
    if (pc->q == 0.0) return 0;
    z_of(md, pc, u0, v0, t0, &z0, &zv0);
    u = z0 - pc->x_eq;
    amp = hypot(u, (zv0 + 0.5 * pc->a * u) / pc->q) + pc->amp;
    return pc->state * (pc->x_eq - pc->state * md->b) > amp * (1.0 + 1e-6);
}

int gd_contact_stays_inside(const double *model, const double *pieces, long piece, double u0,
                            double v0, double t0)
{
    cw_model md = cw_model_of(model);
    cw_piece pc = cw_piece_of(&md, pieces, piece);
    return stays_inside(&md, &pc, u0, v0, t0);
}

/* a bound on |u''| over [s, s + h] from the state (z, zv) of z at s */
static double curvature_bound(const cw_model *md, const cw_piece *pc, double z, double zv,
                              double h)
{
    double a = pc->a, w2 = pc->w2, u, cu, cv, amp_u, amp_v;
    if (pc->state == 0) return fabs(md->w / md->m - a * zv) + pc->curv;
    u = z - pc->x_eq;
    cu = zv + 0.5 * a * u;
    cv = w2 * u + 0.5 * a * zv;
    if (pc->q > 0.0) {
        amp_u = hypot(u, cu / pc->q);
        amp_v = hypot(zv, cv / pc->q);
    } else {
        amp_u = fabs(u) + h * fabs(cu);
        amp_v = fabs(zv) + h * fabs(cv);
    }
    return a * amp_v + w2 * amp_u + pc->curv;
}

double gd_find_root(double (*f)(double, void *), void *ctx, double lo, double hi, double f_lo,
                    double f_hi, double xtol)
{
    int hi_positive = f_hi > 0.0 || (f_hi == 0.0 && f_lo < 0.0), side = 0, it;
    double width = hi - lo;
    for (it = 0; it < 200; it++) {
        double den, t, ft;
        int secant;
        if (hi - lo <= xtol) break;
        den = f_hi - f_lo;
        secant = den != 0.0;
        t = secant ? (lo * f_hi - hi * f_lo) / den : 0.0;
        /* the midpoint also when the secant is degenerate (equal end values) */
        if (!secant || !(lo < t && t < hi) || (it % 2 == 1 && hi - lo > 0.5 * width))
            t = 0.5 * (lo + hi);
        width = hi - lo;
        ft = f(t, ctx);
        if (ft == 0.0) return t;
        if ((ft > 0.0) == hi_positive) {
            hi = t;
            f_hi = ft;
            if (side == -1) f_lo *= 0.5;
            side = -1;
        } else {
            lo = t;
            f_lo = ft;
            if (side == 1) f_hi *= 0.5;
            side = 1;
        }
    }
    return 0.5 * (lo + hi);
}

/* the distance g to one boundary, >= 0 while in the state, and its slope, at s after t0 */
typedef struct {
    const cw_model *md;
    const cw_piece *pc;
    double z0, zv0, t0, level, inside;
} cw_gap;

static void g_eval(const cw_gap *g, double s, double *gv, double *dgv, double *zx, double *zv)
{
    double pu, pv;
    hom(g->md, g->pc, g->z0, g->zv0, s, zx, zv);
    part_at(g->md, g->pc, g->t0 + s, &pu, &pv);
    *gv = (*zx + pu - g->level) * g->inside;
    *dgv = (*zv + pv) * g->inside;
}

static double g_value(double s, void *ctx)
{
    double gv, dgv, zx, zv;
    g_eval((const cw_gap *)ctx, s, &gv, &dgv, &zx, &zv);
    return gv;
}

/* g and its slope, and the slope and its own (g'' = inside u'': the closed form's acceleration
 * about the equilibrium, -a z' - w2 (z - x_eq), or w/m - a z' in the gap; without forcing) */
static void g_and_slope(double s, void *ctx, double *f, double *df)
{
    double zx, zv;
    g_eval((const cw_gap *)ctx, s, f, df, &zx, &zv);
}

static void slope_and_curvature(double s, void *ctx, double *f, double *df)
{
    const cw_gap *g = (const cw_gap *)ctx;
    const cw_form *fm = &g->pc->f;
    double gv, zx, zv;
    g_eval(g, s, &gv, f, &zx, &zv);
    *df = g->inside * (fm->state == 0 ? fm->wm - fm->a * zv
                                      : -(fm->a * zv + fm->w2 * (zx - fm->x_eq)));
}

/* A zero of f in [lo, hi] (f_lo, f_hi of opposite signs), to xtol: Newton steps on f and its
 * derivative (the walk has both from one evaluation of the closed form), from the secant point,
 * each kept in the bracket, which the sign of f at every iterate shrinks; a step that would
 * leave the bracket or does not halve the previous one is replaced by the midpoint (Press et
 * al. 2007, Numerical Recipes, 3rd ed., section 9.4, "rtsafe"). Ends when the bracket is
 * narrower than xtol or a Newton step shorter than xtol / 2 (the quadratic convergence then
 * leaves an error far below the step). Fewer evaluations than gd_find_root's false position
 * on the walk's smooth closed forms. */
static double newton_root(void (*fd)(double, void *, double *, double *), void *ctx,
                          double lo, double hi, double f_lo, double f_hi, double xtol)
{
    int hi_positive = f_hi > 0.0 || (f_hi == 0.0 && f_lo < 0.0), it;
    double den = f_hi - f_lo, x, step = hi - lo;
    x = den != 0.0 ? (lo * f_hi - hi * f_lo) / den : 0.5 * (lo + hi);
    if (!(lo < x && x < hi)) x = 0.5 * (lo + hi);
    for (it = 0; it < 200; it++) {
        double fx, dfx, xn, prev = step;
        fd(x, ctx, &fx, &dfx);
        if (fx == 0.0) return x;
        if ((fx > 0.0) == hi_positive) hi = x; else lo = x;
        if (hi - lo <= xtol) break;
        xn = dfx != 0.0 ? x - fx / dfx : 0.5 * (lo + hi);
        if (!(lo < xn && xn < hi) || fabs(xn - x) > 0.5 * prev) xn = 0.5 * (lo + hi);
        step = fabs(xn - x);
        if (step <= 0.5 * xtol) return xn;
        x = xn;
    }
    return 0.5 * (lo + hi);
}

/* first zero of g in [s0, s1]: each interval is proved free of a zero (g above its chord less
 * the curvature bound's parabola), or g monotone (then a root is closed), else halved, left
 * half first; a tangential graze is bisected down to xtol. Returns 1 with *hit, else 0. */
static int refine(cw_gap *g, double s0, double s1, double g0, double dg0, double c0,
                  double g1, double xtol, double *hit)
{
    double st[CW_STACK][6];
    int top = 0;
    if (!(isfinite(g0) && isfinite(g1))) return 0;
    st[0][0] = s0; st[0][1] = s1; st[0][2] = g0; st[0][3] = dg0; st[0][4] = c0; st[0][5] = g1;
    top = 1;
    while (top > 0) {
        double a, b, ga, dga, ca, gb, wd, mid, gm, dgm, zx, zv, cm;
        top--;
        a = st[top][0]; b = st[top][1]; ga = st[top][2];
        dga = st[top][3]; ca = st[top][4]; gb = st[top][5];
        wd = b - a;
        if (ga > 0.0 && gb > 0.0 && fmin(ga, gb) > ca * wd * wd / 8) continue;
        if (fabs(dga) > ca * wd) {      /* monotone on [a, b] */
            if (gb < 0.0) {
                *hit = newton_root(g_and_slope, g, a, b, ga, gb, xtol);
                return 1;
            }
            continue;
        }
        if (wd <= xtol || top + 2 > CW_STACK) {
            if (gb < 0.0) {
                *hit = b;
                return 1;
            }
            continue;
        }
        mid = 0.5 * (a + b);
        g_eval(g, mid, &gm, &dgm, &zx, &zv);
        cm = curvature_bound(g->md, g->pc, zx, zv, b - mid);
        st[top][0] = mid; st[top][1] = b; st[top][2] = gm;
        st[top][3] = dgm; st[top][4] = cm; st[top][5] = gb;
        top++;
        st[top][0] = a; st[top][1] = mid; st[top][2] = ga;
        st[top][3] = dga; st[top][4] = ca; st[top][5] = gm;
        top++;
    }
    return 0;
}

/* the boundaries a state can leave through, and the sign that makes g >= 0 inside */
static int levels_of(const cw_model *md, const cw_piece *pc, double *level, double *inside)
{
    if (pc->state == 0) {
        level[0] = md->b;
        inside[0] = -1.0;
        level[1] = -md->b;
        inside[1] = 1.0;
        return 2;
    }
    level[0] = pc->state * md->b;
    inside[0] = pc->state == 1 ? 1.0 : -1.0;
    return 1;
}

static int first_crossing(const cw_model *md, const cw_piece *pc, double t0, double u0,
                          double v0, double length, double xtol, double *hit)
{
    double level[2], inside[2], g0[2], dg0[2], z0, zv0, step, nn, s_j, zx, zv, pu, pv, c_j;
    double best = 0.0;
    int nl, l, done[2] = {0, 0}, have = 0, forced = md->nh > 0;
    long n, j;
    cw_gap gap[2];
    if (!(isfinite(u0) && isfinite(v0))) return 0;      /* diverged: nothing to locate */
    if (stays_inside(md, pc, u0, v0, forced ? t0 : 0.0)) return 0;
    if (isfinite(pc->h)) {
        nn = ceil(length / pc->h);
        n = nn > 2.0 ? (long)nn : 2;
    } else {
        n = 4;
    }
    step = length / (double)n;
    z_of(md, pc, u0, v0, t0, &z0, &zv0);
    nl = levels_of(md, pc, level, inside);
    hom(md, pc, z0, zv0, 0.0, &zx, &zv);
    part_at(md, pc, t0, &pu, &pv);
    c_j = forced ? curvature_bound(md, pc, zx, zv, step) : 0.0;
    for (l = 0; l < nl; l++) {
        gap[l].md = md;
        gap[l].pc = pc;
        gap[l].z0 = z0;
        gap[l].zv0 = zv0;
        gap[l].t0 = t0;
        gap[l].level = level[l];
        gap[l].inside = inside[l];
        g0[l] = fabs((zx + pu - level[l]) * inside[l]);  /* starts on or inside the boundary */
        dg0[l] = (zv + pv) * inside[l];
    }
    s_j = 0.0;
    for (j = 0; j < n; j++) {
        double s1 = j + 1 == n ? length : (double)(j + 1) * step, c1 = 0.0;
        int open = 0;
        hom(md, pc, z0, zv0, s1, &zx, &zv);
        part_at(md, pc, t0 + s1, &pu, &pv);
        if (forced) c1 = curvature_bound(md, pc, zx, zv, step);
        for (l = 0; l < nl; l++) {
            double g1 = (zx + pu - level[l]) * inside[l], dg1 = (zv + pv) * inside[l], h1;
            int found = 0;
            if (done[l]) continue;
            if (have && s_j >= best) {
                done[l] = 1;
                continue;
            }
            if (forced) {
                int clear = (g0[l] > 0.0 && g1 > 0.0 && fmin(g0[l], g1) > c_j * step * step / 8)
                            || (fabs(dg0[l]) > c_j * step && g1 >= 0.0);
                if (!clear)
                    found = refine(&gap[l], s_j, s1, g0[l], dg0[l], c_j, g1, xtol, &h1);
            } else if (g1 < 0.0) {      /* a sign change */
                h1 = newton_root(g_and_slope, &gap[l], s_j, s1, g0[l], g1, xtol);
                found = 1;
            } else if (dg0[l] < 0.0 && dg1 > 0.0) {     /* a minimum of g inside */
                double sm = newton_root(slope_and_curvature, &gap[l], s_j, s1, dg0[l], dg1,
                                       xtol);
                double gm = g_value(sm, &gap[l]);
                if (gm < 0.0) {         /* dips below the boundary and returns */
                    h1 = newton_root(g_and_slope, &gap[l], s_j, sm, g0[l], gm, xtol);
                    found = 1;
                }
            }
            if (found) {
                done[l] = 1;
                if (!have || h1 < best) best = h1;
                have = 1;
                continue;
            }
            g0[l] = g1;
            dg0[l] = dg1;
            open = 1;
        }
        if (!open) break;
        s_j = s1;
        c_j = c1;
    }
    if (have) *hit = best;
    return have;
}

int gd_contact_first_crossing(const double *model, const double *pieces, long piece, double t0,
                              double u0, double v0, double length, double xtol, double *hit)
{
    cw_model md = cw_model_of(model);
    cw_piece pc = cw_piece_of(&md, pieces, piece);
    return first_crossing(&md, &pc, t0, u0, v0, length, xtol, hit);
}

/* the contact state of (x, v) and the one entered at a located change */
static int state_at(double x, double v, double b)
{
    if (x > b || (x == b && v > 0)) return 1;
    if (x < -b || (x == -b && v < 0)) return -1;
    return 0;
}

static int next_state(int state, double x, double v)
{
    if (state == 0) return v > 0 || x > 0 ? 1 : -1;
    return 0;
}

/* phi <- exp(A s) phi for one contact state (the closed form with unit starts, no load, from
 * the terms e at s), and the same for part (NULL: none), the sensitivity since the start of its
 * slot */
static void transition(const cw_form *f, const cw_terms *e, double *phi, double *part)
{
    double t[4];
    int j;
    form_apply(f, e, 0.0, 0.0, 1.0, 0.0, t, t + 2);
    form_apply(f, e, 0.0, 0.0, 0.0, 1.0, t + 1, t + 3);
    for (j = 0; j < 2; j++) {
        double *p = j ? part : phi, p0, p1, p2, p3;
        if (!p) continue;
        p0 = p[0]; p1 = p[1]; p2 = p[2]; p3 = p[3];
        p[0] = t[0] * p0 + t[1] * p2;
        p[1] = t[0] * p1 + t[1] * p3;
        p[2] = t[2] * p0 + t[3] * p2;
        p[3] = t[2] * p1 + t[3] * p3;
    }
}

/* the saltation [[1, 0], [r, 1]] (r NaN: no derivative) applied to p */
static void saltate(double r, double *p)
{
    if (!p) return;
    if (isnan(r)) {
        p[0] = p[1] = p[2] = p[3] = NAN;
        return;
    }
    p[2] += r * p[0];
    p[3] += r * p[1];
}

/* (w - c v - spring) / m: the field's acceleration without the forcing, which is the same on
 * both sides of a contact change */
static double accel(const cw_model *md, int state, double k, double x, double v)
{
    double spring = state == 0 ? 0.0 : k * (x - state * md->b);
    return (md->w - md->c * v - spring) / md->m;
}

/* the explicit derivative of a piece's particular solution with respect to the parameter at
 * a fixed time t: d u_p / dp, d u_p' / dp from the coefficients' derivatives dca, dcb (2 nh
 * per row of dpieces) and the phase's, d th_n / dp = tn t dfm (th_n = tn (fm t + p0)) */
static void part_dp(const cw_model *md, const cw_piece *pc, const double *drow, double dfm,
                    double t, double *du, double *dv)
{
    double p, u = 0.0, v = 0.0;
    long i;
    if (md->nh > 0) {
        p = fmod(md->fm * t + md->p0, 1.0);
        for (i = 0; i < md->nh; i++) {
            double cs = cos(md->tn[i] * p), sn = sin(md->tn[i] * p), dth = md->tn[i] * t * dfm;
            double ca = pc->ca[i], cb = pc->cb[i], da = drow[i], db = drow[md->nh + i];
            double om = md->om[i], dom = md->tn[i] * dfm;
            u += da * cs + db * sn + dth * (cb * cs - ca * sn);
            v += dom * (cb * cs - ca * sn) + om * (db * cs - da * sn)
                 - om * dth * (cb * sn + ca * cs);
        }
    }
    *du = u;
    *dv = v;
}

/* the forcing g(t) = u_p'' + a u_p' + w2 u_p of a piece (zero without harmonics) */
static double forcing_at(const cw_model *md, const cw_piece *pc, double t)
{
    double p, u = 0.0, v = 0.0, acc = 0.0;
    long i;
    if (md->nh == 0) return 0.0;
    p = fmod(md->fm * t + md->p0, 1.0);
    for (i = 0; i < md->nh; i++) {
        double cs = cos(md->tn[i] * p), sn = sin(md->tn[i] * p), om = md->om[i];
        double val = pc->ca[i] * cs + pc->cb[i] * sn;
        u += val;
        v += om * (pc->cb[i] * cs - pc->ca[i] * sn);
        acc -= om * om * val;
    }
    return acc + pc->a * v + pc->w2 * u;
}

int gd_contact_walk(const double *model, const double *pieces, long n_cuts, const double *cuts,
                    const long *kidx, double u0, double v0, double xtol, long max_events,
                    long cap, double *seg, long *seg_id, long *n_seg, double *out,
                    const long *slot, double *phis, const double *rates,
                    const double *dpieces, double *dpar)
{
    cw_model md = cw_model_of(model);
    double x = u0, v = v0, b = md.b, phi[4] = {1.0, 0.0, 0.0, 1.0};
    double dfm = rates && dpar ? dpar[2] : 0.0, *sp = rates ? dpar : NULL;
    int state = state_at(x, v, b), status = GD_CW_OK, grazed = 0;
    long i, ns = 0, last_row = -1, width = GD_CW_ROW + 2 * md.nh;
    out[6] = 0.0;
    if (sp && n_cuts > 0) {             /* the start moving: minus the field there */
        cw_piece pc = cw_piece_of(&md, pieces, 3 * kidx[0] + state + 1);
        sp[0] -= rates[0] * v;
        sp[1] -= rates[0] * (accel(&md, state, pc.k, x, v) + forcing_at(&md, &pc, cuts[0]));
    }
    for (i = 0; i < n_cuts && status == GD_CW_OK; i++) {
        double t = cuts[i], tb = cuts[i + 1], *part = phis && slot ? phis + 4 * slot[i] : NULL;
        long n_ev = 0;
        if (sp && i > 0 && kidx[i] != kidx[i - 1]) {
            /* a stiffness switch moving at rates[i]: (f- - f+) rates[i], the fields of the
             * piece before and after at the switch (the forcing is the same in both) */
            double k0 = pieces[(size_t)(3 * kidx[i - 1] + state + 1) * (size_t)width + 1];
            double k1 = pieces[(size_t)(3 * kidx[i] + state + 1) * (size_t)width + 1];
            sp[1] += rates[i] * (accel(&md, state, k0, x, v) - accel(&md, state, k1, x, v));
        }
        while (t < tb) {
            long row = 3 * kidx[i] + state + 1;
            cw_piece pc = cw_piece_of(&md, pieces, row);
            double hit = 0.0, s, z0, zv0, xn, vn;
            cw_terms e;
            int ev = first_crossing(&md, &pc, t, x, v, tb - t, xtol, &hit) && t + hit < tb;
            s = ev ? hit : tb - t;
            if (ns < cap) {
                seg[4 * ns] = t;
                seg[4 * ns + 1] = x;
                seg[4 * ns + 2] = v;
                seg[4 * ns + 3] = s;
                seg_id[2 * ns] = row;
                seg_id[2 * ns + 1] = ev;
            }
            ns++;
            last_row = row;
            z_of(&md, &pc, x, v, t, &z0, &zv0);
            form_terms(&pc.f, s, &e);   /* once for the end state and its sensitivity */
            form_apply(&pc.f, &e, pc.f.x_eq, pc.f.wm, z0, zv0, &xn, &vn);
            if (md.nh > 0) {
                double pu, pv;
                part_at(&md, &pc, t + s, &pu, &pv);
                xn += pu;
                vn += pv;
            }
            if (sp) {
                /* s(t + s) = H (s(t) - du_p(t)) + du_p(t + s): H the piece's transition */
                double h[4] = {1.0, 0.0, 0.0, 1.0}, da = 0.0, dv = 0.0, d0, d1;
                transition(&pc.f, &e, h, NULL);
                if (dpieces) part_dp(&md, &pc, dpieces + (size_t)row * (size_t)(2 * md.nh),
                                     dfm, t, &da, &dv);
                d0 = sp[0] - da;
                d1 = sp[1] - dv;
                sp[0] = h[0] * d0 + h[1] * d1;
                sp[1] = h[2] * d0 + h[3] * d1;
                if (dpieces) {
                    part_dp(&md, &pc, dpieces + (size_t)row * (size_t)(2 * md.nh), dfm, t + s,
                            &da, &dv);
                    sp[0] += da;
                    sp[1] += dv;
                }
            }
            transition(&pc.f, &e, phi, part);
            x = xn;
            v = vn;
            if (!ev) {
                t = tb;
                break;
            }
            t = t + hit;
            x = fabs(x - b) < fabs(x + b) ? b : -b;     /* exactly on the boundary crossed */
            {
                int nxt = next_state(state, x, v);
                double f_minus = accel(&md, state, pc.k, x, v);
                double f_plus = accel(&md, nxt, pc.k, x, v);
                if (f_plus != f_minus) {        /* saltation I + (f+ - f-) n^T / (n^T f-) */
                    double r = NAN;
                    if (v != 0.0) {
                        r = (f_plus - f_minus) / v;
                    } else {                    /* no derivative: the walk goes on, phi NaN */
                        if (!grazed) out[6] = t;
                        grazed = 1;
                    }
                    saltate(r, phi);
                    saltate(r, part);
                    if (sp) {                   /* the surface u = +-b does not move */
                        if (isnan(r)) {
                            sp[0] = sp[1] = NAN;
                        } else {
                            sp[1] += r * sp[0];
                        }
                    }
                }
                state = nxt;
            }
            if (++n_ev > max_events) {
                out[6] = t;
                status = GD_CW_CHATTER;
                break;
            }
        }
    }
    if (sp && last_row >= 0) {          /* the end moving: the field of the last piece there */
        cw_piece pc = cw_piece_of(&md, pieces, last_row);
        sp[0] += rates[n_cuts] * v;
        sp[1] += rates[n_cuts] * (accel(&md, state, pc.k, x, v)
                                  + forcing_at(&md, &pc, cuts[n_cuts]));
    }
    out[0] = x;
    out[1] = v;
    memcpy(out + 2, phi, sizeof phi);
    *n_seg = ns;
    if (status == GD_CW_OK && ns > cap) status = GD_CW_FULL;
    if (status == GD_CW_OK && grazed) status = GD_CW_GRAZE;
    return status;
}

/* Sampling a segment on a uniform grid: the states at s_a + j dt (j < CW_RUN) from an anchor
 * s_a, by the addition theorems, with the terms at j dt tabulated once per piece row (the
 * rows are few, the samples many):
 *   underdamped, z - x_eq = e^{-a s/2} (A cos qs + B sin qs):
 *     at s_a + j dt  = C_j P + S_j Q,  C_j, S_j = e^{-a j dt/2} (cos, sin)(q j dt),
 *     P = D (A c + B n), Q = D (B c - A n), D, c, n = e^{-a s_a/2}, cos, sin (q s_a);
 *   gap, e1(s) = (1 - e^{-a s}) / a:  e1(s_a + j dt) = e1(s_a) + e^{-a s_a} e1(j dt).
 * Each term is a direct evaluation (no recurrence: the error does not grow with j). A sample
 * whose time is off s_a + j dt by d (the grid's rounding) is moved there along the flow,
 * x += v d, v += x'' d; where (q + a) |d| > 1e-8 (not uniform: the second-order term would
 * exceed rounding) it is evaluated directly. */
#define CW_RUN 64

typedef struct {
    long filled;                /* terms tabulated: j < filled */
    double c[CW_RUN], n[CW_RUN];
} cw_run;

static void run_fill(const cw_form *f, double dt, long upto, cw_run *r)
{
    for (; r->filled <= upto; r->filled++) {
        double s = (double)r->filled * dt;
        if (f->kind == 1) {
            double d = exp(-0.5 * f->a * s);
            r->c[r->filled] = d * cos(f->q * s);
            r->n[r->filled] = d * sin(f->q * s);
        } else {                        /* the damped gap */
            r->c[r->filled] = -expm1(-f->a * s) / f->a;
            r->n[r->filled] = exp(-f->a * s);
        }
    }
}

int gd_contact_on_grid(const double *model, const double *pieces, long n_seg, const double *seg,
                       const long *seg_id, long n_t, const double *t, double *out)
{
    cw_model md = cw_model_of(model);
    long i, o = 0, cached = -1, anchor = 0, n_rows = 0;
    double z0 = 0.0, zv0 = 0.0, dt = 0.0, s_a = 0.0, an[4] = {0.0, 0.0, 0.0, 0.0};
    cw_piece pc;
    cw_run *runs = NULL, *run = NULL;
    int bad = 0;
    if (n_seg < 1) return 1;
    for (i = 0; i < n_seg; i++)
        if (seg_id[2 * i] + 1 > n_rows) n_rows = seg_id[2 * i] + 1;
    if (n_t > 2) {
        dt = (t[n_t - 1] - t[0]) / (double)(n_t - 1);
        if (isfinite(dt) && dt > 0.0) runs = calloc((size_t)n_rows, sizeof(cw_run));
    }
    pc = cw_piece_of(&md, pieces, seg_id[0]);
    for (i = 0; i < n_t; i++) {
        double ti = t[i];
        while (o + 1 < n_seg && seg[4 * o] <= ti && seg[4 * (o + 1)] <= ti
               && (o + 2 == n_seg || ti < seg[4 * (o + 2)]))
            o++;                        /* the next segment (in order, the usual case) */
        if (!(o < n_seg && seg[4 * o] <= ti && (o + 1 == n_seg || ti < seg[4 * (o + 1)]))) {
            long lo = 0, hi = n_seg;          /* the last segment starting at or before ti */
            while (hi - lo > 1) {
                long mid = lo + (hi - lo) / 2;
                if (seg[4 * mid] <= ti) lo = mid; else hi = mid;
            }
            o = lo;
        }
        if (o != cached) {              /* the state of z = u - u_p at this segment's start */
            pc = cw_piece_of(&md, pieces, seg_id[2 * o]);
            z_of(&md, &pc, seg[4 * o + 1], seg[4 * o + 2], seg[4 * o], &z0, &zv0);
            cached = o;
            run = runs && (pc.f.kind == 1 || pc.f.kind == 4) ? runs + seg_id[2 * o] : NULL;
            anchor = -CW_RUN;
        }
        if (run) {
            const cw_form *f = &pc.f;
            double s = ti - seg[4 * o], d, x, v;
            long j = i - anchor;
            if (j >= CW_RUN || j < 0) {         /* a new anchor at this sample */
                anchor = i;
                j = 0;
                s_a = s;
                if (f->kind == 1) {
                    double u = z0 - f->x_eq, bx = (zv0 + 0.5 * f->a * u) / f->q;
                    double bv = -(f->w2 * u + 0.5 * f->a * zv0) / f->q;
                    double dd = exp(-0.5 * f->a * s), c = dd * cos(f->q * s),
                           n = dd * sin(f->q * s);
                    an[0] = u * c + bx * n;
                    an[1] = bx * c - u * n;
                    an[2] = zv0 * c + bv * n;
                    an[3] = bv * c - zv0 * n;
                } else {
                    an[0] = -expm1(-f->a * s) / f->a;
                    an[1] = exp(-f->a * s);
                }
            }
            d = s - (s_a + (double)j * dt);
            if (fabs(d) * (f->q + f->a) <= 1e-8) {
                if (j >= run->filled) run_fill(f, dt, j, run);
                if (f->kind == 1) {
                    double xr = run->c[j] * an[0] + run->n[j] * an[1];
                    v = run->c[j] * an[2] + run->n[j] * an[3];
                    x = f->x_eq + xr + v * d;
                    v -= (f->a * v + f->w2 * xr) * d;
                } else {
                    double e1 = an[0] + an[1] * run->c[j], sj = s - d;
                    x = z0 + zv0 * e1 + f->wm * (sj - e1) / f->a;
                    v = zv0 + (f->wm - f->a * zv0) * e1;
                    x += v * d;
                    v += (f->wm - f->a * v) * d;
                }
                if (md.nh > 0) {
                    double pu, pv;
                    part_at(&md, &pc, ti, &pu, &pv);
                    x += pu;
                    v += pv;
                }
                out[i] = x;
                out[n_t + i] = v;
                if (!(isfinite(x) && isfinite(v))) bad = 1;
                continue;
            }
        }
        piece_eval(&md, &pc, z0, zv0, ti - seg[4 * o], ti, out + i, out + n_t + i);
        if (!(isfinite(out[i]) && isfinite(out[n_t + i]))) bad = 1;
    }
    free(runs);
    return bad;
}
