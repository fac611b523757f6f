/* gear_dyn kernel: the steppers of gd_kernel.c / gd_torsional.c over an output grid in one call,
 * for the solvers' ``kernel`` method (gear_dyn.solvers.kernel.run). The FMU does not compile
 * this file: it advances the same state one communication point at a time. */
#include <math.h>
#include "gd_kernel.h"

long gd_run(gd_state *s, const gd_model *m, long n, const double *t, double *y, double *coef,
            int *status)
{
    int ns = m->tors ? 4 : 2, j;
    long i;
    /* the torsional model's mesh phase from the time at each output, p0 + f_m (t - t0) within
     * the table's period (the speed is constant over a run): summed over the steps to every
     * output, as the FMU does, it would drift by rounding, to 1e-9 of a cycle over a hunting
     * period of 630 cycles */
    double t0 = s->t, p0 = s->frac, fm = m->z1 * s->par[GD_SPEED] / (2.0 * 3.14159265358979323846);
    double period = m->breaks[m->n_pieces];
    *status = GD_OK;
    for (i = 0; i < n; i++) {
        const double *q = m->tors ? s->q : 0;
        if (t[i] > s->t) {
            *status = gd_advance(s, m, t[i]);
            if (*status != GD_OK) return i;
            if (q) {
                double p = fmod(p0 + fm * (s->t - t0), period);
                s->frac = fmin(fmax(p, m->breaks[s->piece]), m->breaks[s->piece + 1]);
            }
        }
        if (!q) {
            y[2 * i] = s->x;
            y[2 * i + 1] = s->v;
        } else {
            for (j = 0; j < 4; j++) y[4 * i + j] = q[j];
            if (coef) gd_tors_coef(s, m, coef + 5 * i);
        }
        for (j = 0; j < ns; j++) {
            if (!isfinite(y[ns * i + j])) {
                *status = GD_ERR_STEP;
                return i;
            }
        }
    }
    return n;
}
