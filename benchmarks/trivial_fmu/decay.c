/* The trivial FMU's model (see decay.h). */
#include <math.h>

#include "decay.h"

void decay_reset(Decay *m) {
    m->time = 0.0;
    m->x = 1.0;
    m->k = 1.0;
    m->phase = PHASE_INSTANTIATED;
}

void decay_step(Decay *m, double h) {
    m->x *= exp(-m->k * h);
    m->time += h;
}

int decay_get(const Decay *m, unsigned vr, double *value) {
    switch (vr) {
    case VR_TIME: *value = m->time; return 0;
    case VR_X: *value = m->x; return 0;
    case VR_K: *value = m->k; return 0;
    default: return -1;
    }
}

const char *decay_set(Decay *m, unsigned vr, double value) {
    if (vr != VR_K) return "only k (value reference 2) can be set";
    if (m->phase != PHASE_INSTANTIATED && m->phase != PHASE_INITIALIZATION)
        return "k is fixed after initialization";
    if (!(value >= 0.0 && value <= 1e6)) return "k must be in [0, 1e6] 1/s";
    m->k = value;
    return NULL;
}
