/* The trivial FMU's model: one state x with dx/dt = -k x, stepped exactly.
 *
 * The floor of benchmarks/bench_native_fmu.py: an FMU that does as little as an FMU can (one
 * multiplication by exp(-k h) per step), built and shipped the way gear_dyn's native FMU is
 * (C99, libm only, compiled with the system compiler, sources in the FMU). Shared by the FMI 2
 * glue (fmi2_glue.c) and the FMI 3 glue (fmi3_glue.c).
 */
#ifndef DECAY_H
#define DECAY_H

#include <stddef.h>

/* FMI 2 guid and FMI 3 instantiationToken (also in the modelDescription.xml files) */
#define DECAY_GUID "{5e1f6c0a-9d27-4b8e-a0c3-7d2b1f4e8a61}"

/* value references (FMI 3 also has the independent variable time = 0) */
enum { VR_TIME = 0, VR_X = 1, VR_K = 2 };

/* life cycle of an instance, as both FMI versions name it */
typedef enum { PHASE_INSTANTIATED, PHASE_INITIALIZATION, PHASE_STEPPING, PHASE_TERMINATED } Phase;

/* the whole model state: the FMU state (get, set, serialize) is a copy of this struct */
typedef struct {
    double time; /* s */
    double x;    /* 1, the output */
    double k;    /* 1/s, decay rate, parameter in [0, 1e6] */
    Phase phase;
} Decay;

/* start values */
void decay_reset(Decay *m);
/* advance by h seconds (exact: x <- x exp(-k h)) */
void decay_step(Decay *m, double h);
/* read a Float64 variable; 0 on success, -1 for an unknown value reference */
int decay_get(const Decay *m, unsigned vr, double *value);
/* write a Float64 variable; NULL on success, else why it was refused (a static message) */
const char *decay_set(Decay *m, unsigned vr, double value);

#endif
