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
    *status = GD_OK;
    for (i = 0; i < n; i++) {
        const double *q = m->tors ? s->q : 0;
        if (t[i] > s->t) {
            *status = gd_advance(s, m, t[i]);
            if (*status != GD_OK) return i;
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
