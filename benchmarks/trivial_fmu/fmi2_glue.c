/* FMI 2.0 co-simulation interface of the trivial FMU (model in decay.c).
 *
 * Every function of the FMI 2 co-simulation API is defined; what the model does not support
 * (integers, strings, derivatives, asynchronous steps) returns fmi2Error with a message.
 */
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "decay.h"

typedef struct {
    Decay model;
    const fmi2CallbackFunctions *cb;
    char name[64];
    int logging;
} Instance;

static fmi2Status fail(fmi2Component c, const char *function, const char *why) {
    Instance *inst = (Instance *)c;
    if (inst && inst->cb && inst->cb->logger)
        inst->cb->logger(inst->cb->componentEnvironment, inst->name, fmi2Error, "logStatusError",
                         "%s: %s", function, why);
    return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                               const fmi2String categories[]) {
    (void)n, (void)categories;
    ((Instance *)c)->logging = on;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String resources, const fmi2CallbackFunctions *cb,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)resources, (void)visible;
    if (type != fmi2CoSimulation || !guid || strcmp(guid, DECAY_GUID) != 0) return NULL;
    Instance *inst = (Instance *)calloc(1, sizeof(Instance));
    if (!inst) return NULL;
    decay_reset(&inst->model);
    inst->cb = cb;
    inst->logging = logging;
    strncpy(inst->name, name ? name : "", sizeof inst->name - 1);
    return inst;
}

void fmi2FreeInstance(fmi2Component c) { free(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol,
                               fmi2Real start, fmi2Boolean stopDefined, fmi2Real stop) {
    (void)tolDefined, (void)tol, (void)stopDefined, (void)stop;
    ((Instance *)c)->model.time = start;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Instance *)c)->model.phase = PHASE_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    ((Instance *)c)->model.phase = PHASE_STEPPING;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    ((Instance *)c)->model.phase = PHASE_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    decay_reset(&((Instance *)c)->model);
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       fmi2Real value[]) {
    for (size_t i = 0; i < n; i++)
        if (decay_get(&((Instance *)c)->model, vr[i], &value[i]) != 0)
            return fail(c, "fmi2GetReal", "unknown value reference");
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real value[]) {
    for (size_t i = 0; i < n; i++) {
        const char *why = decay_set(&((Instance *)c)->model, vr[i], value[i]);
        if (why) return fail(c, "fmi2SetReal", why);
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          fmi2Integer value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2GetInteger", "the model has no Integer variables") : fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          const fmi2Integer value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2SetInteger", "the model has no Integer variables") : fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          fmi2Boolean value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2GetBoolean", "the model has no Boolean variables") : fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          const fmi2Boolean value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2SetBoolean", "the model has no Boolean variables") : fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                         fmi2String value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2GetString", "the model has no String variables") : fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                         const fmi2String value[]) {
    (void)vr, (void)value;
    return n ? fail(c, "fmi2SetString", "the model has no String variables") : fmi2OK;
}

/* FMU state: a heap copy of the model struct */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    if (!*state) *state = malloc(sizeof(Decay));
    if (!*state) return fail(c, "fmi2GetFMUstate", "out of memory");
    memcpy(*state, &((Instance *)c)->model, sizeof(Decay));
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    if (!state) return fail(c, "fmi2SetFMUstate", "no state");
    memcpy(&((Instance *)c)->model, state, sizeof(Decay));
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    (void)c;
    free(*state);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    (void)c, (void)state;
    *size = sizeof(Decay);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                 size_t size) {
    if (size != sizeof(Decay)) return fail(c, "fmi2SerializeFMUstate", "wrong size");
    memcpy(bytes, state, sizeof(Decay));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                   fmi2FMUstate *state) {
    if (size != sizeof(Decay)) return fail(c, "fmi2DeSerializeFMUstate", "wrong size");
    if (!*state) *state = malloc(sizeof(Decay));
    if (!*state) return fail(c, "fmi2DeSerializeFMUstate", "out of memory");
    memcpy(*state, bytes, sizeof(Decay));
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                        size_t nu, const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real dv[], fmi2Real dz[]) {
    (void)u, (void)nu, (void)z, (void)nz, (void)dv, (void)dz;
    return fail(c, "fmi2GetDirectionalDerivative", "not provided");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                       size_t n, const fmi2Integer order[],
                                       const fmi2Real value[]) {
    (void)vr, (void)n, (void)order, (void)value;
    return fail(c, "fmi2SetRealInputDerivatives", "the model has no inputs");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t n, const fmi2Integer order[],
                                        fmi2Real value[]) {
    (void)vr, (void)n, (void)order, (void)value;
    return fail(c, "fmi2GetRealOutputDerivatives", "not provided");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Instance *inst = (Instance *)c;
    (void)t, (void)noSetPrior;
    if (inst->model.phase != PHASE_STEPPING) return fail(c, "fmi2DoStep", "not initialized");
    if (!(h >= 0.0)) return fail(c, "fmi2DoStep", "negative step");
    decay_step(&inst->model, h);
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    return fail(c, "fmi2CancelStep", "steps are synchronous");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s, (void)value;
    return fail(c, "fmi2GetStatus", "steps are synchronous");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    (void)s, (void)value;
    return fail(c, "fmi2GetRealStatus", "steps are synchronous");
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s, (void)value;
    return fail(c, "fmi2GetIntegerStatus", "steps are synchronous");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)s, (void)value;
    return fail(c, "fmi2GetBooleanStatus", "steps are synchronous");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s, (void)value;
    return fail(c, "fmi2GetStringStatus", "steps are synchronous");
}
