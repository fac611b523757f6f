/* gear_dyn kernel: the steppers of gd_kernel.c / gd_torsional.c over an output grid in one call,
 * for the solvers' ``kernel`` method (gear_dyn.solvers.kernel.run): the single-DOF model
 * advanced to each output time, the torsional model by gd_tors_run. The FMU does not compile
 * this file: it advances the same state one communication point at a time. */
#include <math.h>
#include "gd_kernel.h"

long gd_run(gd_state *s, const gd_model *m, long n, const double *t, double *y, double *coef,
            int *status)
{
    long i;
    *status = GD_OK;
    if (m->tors) return gd_tors_run(s, m, n, t, y, coef, status);
    for (i = 0; i < n; i++) {
        if (t[i] > s->t) {
            *status = gd_advance(s, m, t[i]);
            if (*status != GD_OK) return i;
        }
        y[2 * i] = s->x;
        y[2 * i + 1] = s->v;
        if (!isfinite(y[2 * i]) || !isfinite(y[2 * i + 1])) {
            *status = GD_ERR_STEP;
            return i;
        }
    }
    return n;
}
