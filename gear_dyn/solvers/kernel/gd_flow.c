/* gear_dyn flow kernel (see gd_flow.h): products and applications of affine step maps. The
 * maps themselves (matrix exponentials of the pieces, collocation maps) come from Python; only
 * the sequential part, which numpy would run one small product per Python iteration, is here. */
#include <math.h>
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
