/* gear_dyn flow kernel (see gd_flow.h): the linear single-DOF model over many speeds at once
 * (gear_dyn.solvers.linear_maps builds the phase rows and reads the products). Each step is the
 * exponential of its augmented generator [[B, f], [0, 0]] in closed form: exact for constant
 * coefficients, the fourth-order Magnus step with two Gauss points otherwise (Blanes, Casas,
 * Oteo & Ros 2009, eq. 4.6). */
#include <math.h>
#include <string.h>
#include "gd_flow.h"

#define C3 0.14433756729740644113   /* sqrt(3) / 12 */

/* E = exp(B), 2x2 row-major, by Cayley-Hamilton: with mu = tr(B) / 2 and
 * d2 = ((b11 - b22) / 2)^2 + b12 b21 (so (B - mu I)^2 = d2 I),
 * exp(B) = e^mu (C I + S (B - mu I)), C = cosh(sqrt(d2)), S = sinh(sqrt(d2)) / sqrt(d2)
 * (cos and sin of sqrt(-d2) where d2 < 0; the series of S where |d2| is small) */
static void expm2(const double *b, double *e)
{
    double mu = 0.5 * (b[0] + b[3]), half = 0.5 * (b[0] - b[3]);
    double d2 = half * half + b[1] * b[2];
    double s = sqrt(fabs(d2)), c, sh, em;
    if (d2 < 0) {
        c = cos(s);
        sh = s < 1e-4 ? 1.0 + d2 / 6.0 + d2 * d2 / 120.0 : sin(s) / s;
    } else {
        c = cosh(s);
        sh = s < 1e-4 ? 1.0 + d2 / 6.0 + d2 * d2 / 120.0 : sinh(s) / s;
    }
    em = exp(mu);
    e[0] = em * (c + sh * half);
    e[1] = em * sh * b[1];
    e[2] = em * sh * b[2];
    e[3] = em * (c - sh * half);
}

void gd_lin_expm2(long n, const double *B, double *E)
{
    long i;
    for (i = 0; i < n; i++) expm2(B + 4 * i, E + 4 * i);
}

/* the map y -> E y + q of one step: row (GD_LIN_ROW values, gd_flow.h) at mesh frequency fm */
static void step_map(const double *row, double fm, double *e, double *q)
{
    double h = row[0] / fm, ka = row[1], kb = row[2], gam = row[3];
    double ga = row[4] + fm * row[6], gb = row[5] + fm * row[7];
    double d = ka - kb, c3 = C3 * h * h, b[4], f0, f1, det;
    b[0] = -c3 * d;
    b[1] = h;
    b[2] = -0.5 * h * (ka + kb) + c3 * gam * d;
    b[3] = -h * gam + c3 * d;
    f0 = c3 * (ga - gb);
    f1 = 0.5 * h * (ga + gb) - c3 * gam * (ga - gb);
    expm2(b, e);
    det = b[0] * b[3] - b[1] * b[2];
    if (det != 0.0) {                   /* q = (I - E) y*, y* = -B^-1 f the step's equilibrium */
        double y0 = -(b[3] * f0 - b[1] * f1) / det, y1 = -(b[0] * f1 - b[2] * f0) / det;
        q[0] = (1.0 - e[0]) * y0 - e[1] * y1;
        q[1] = -e[2] * y0 + (1.0 - e[3]) * y1;
    } else {                            /* B = 0 (a step of zero length): q = f */
        q[0] = f0;
        q[1] = f1;
    }
}

static const double *lane_rows(long n_steps, const double *rows, const long *table, long lane)
{
    return rows + (size_t)(table ? table[lane] : 0) * (size_t)n_steps * GD_LIN_ROW;
}

void gd_lin_maps(long n_lanes, long n_steps, const double *rows, const long *table,
                 const double *fm, double *F, double *h)
{
    long s, i;
    for (s = 0; s < n_lanes; s++) {
        const double *r = lane_rows(n_steps, rows, table, s);
        size_t at = (size_t)s * (size_t)n_steps;
        for (i = 0; i < n_steps; i++)
            step_map(r + (size_t)i * GD_LIN_ROW, fm[s], F + 4 * (at + (size_t)i),
                     h + 2 * (at + (size_t)i));
    }
}

void gd_lin_period(long n_lanes, long n_steps, const double *rows, const long *table,
                   const double *fm, long n_keep, const long *keep, double *Q, double *R)
{
    long s, i, k;
    for (s = 0; s < n_lanes; s++) {
        const double *r = lane_rows(n_steps, rows, table, s);
        double p[4] = {1.0, 0.0, 0.0, 1.0}, u[2] = {0.0, 0.0}, e[4], q[2], t[4], v0;
        size_t at = (size_t)s * (size_t)n_keep;
        for (i = 0, k = 0; i < n_steps; i++) {
            step_map(r + (size_t)i * GD_LIN_ROW, fm[s], e, q);
            t[0] = e[0] * p[0] + e[1] * p[2];
            t[1] = e[0] * p[1] + e[1] * p[3];
            t[2] = e[2] * p[0] + e[3] * p[2];
            t[3] = e[2] * p[1] + e[3] * p[3];
            memcpy(p, t, sizeof p);
            v0 = e[0] * u[0] + e[1] * u[1] + q[0];
            u[1] = e[2] * u[0] + e[3] * u[1] + q[1];
            u[0] = v0;
            if (k < n_keep && keep[k] == i) {
                memcpy(Q + 4 * (at + (size_t)k), p, sizeof p);
                memcpy(R + 2 * (at + (size_t)k), u, sizeof u);
                k++;
            }
        }
    }
}

void gd_lin_chain(long n_lanes, long n_steps, const double *F, const double *h, double *Y)
{
    long s, i;
    for (s = 0; s < n_lanes; s++) {
        const double *hs = h + 2 * (size_t)s * (size_t)n_steps;
        double *y = Y + 2 * (size_t)s * (size_t)(n_steps + 1);
        y[0] = y[1] = 0.0;
        for (i = 0; i < n_steps; i++, y += 2) {
            const double *e = F + 4 * (size_t)i;
            y[2] = e[0] * y[0] + e[1] * y[1] + hs[2 * i];
            y[3] = e[2] * y[0] + e[3] * y[1] + hs[2 * i + 1];
        }
    }
}
