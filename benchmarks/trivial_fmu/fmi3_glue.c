/* FMI 3.0 co-simulation interface of the trivial FMU (model in decay.c).
 *
 * Every function of the FMI 3 API is defined; what the model does not support (other types,
 * clocks, model exchange, scheduled execution, derivatives) returns fmi3Error with a message.
 */
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "decay.h"

typedef struct {
    Decay model;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    char name[64];
} Instance;

static fmi3Status fail(fmi3Instance c, const char *function, const char *why) {
    Instance *inst = (Instance *)c;
    char message[256];
    if (inst && inst->log) {
        strcpy(message, function);
        strncat(message, ": ", sizeof message - strlen(message) - 1);
        strncat(message, why, sizeof message - strlen(message) - 1);
        inst->log(inst->env, fmi3Error, "logStatusError", message);
    }
    return fmi3Error;
}

#define UNSUPPORTED(function) return fail(instance, #function, "not supported by this model")

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean on, size_t n,
                               const fmi3String categories[]) {
    (void)instance, (void)on, (void)n, (void)categories;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token,
                                          fmi3String resources, fmi3Boolean visible,
                                          fmi3Boolean logging, fmi3InstanceEnvironment env,
                                          fmi3LogMessageCallback log) {
    (void)name, (void)token, (void)resources, (void)visible, (void)logging, (void)env, (void)log;
    return NULL; /* co-simulation only */
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token,
                                         fmi3String resources, fmi3Boolean visible,
                                         fmi3Boolean logging, fmi3Boolean eventModeUsed,
                                         fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference required[], size_t nRequired,
                                         fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
                                         fmi3IntermediateUpdateCallback intermediate) {
    (void)resources, (void)visible, (void)logging, (void)earlyReturnAllowed, (void)required,
        (void)nRequired, (void)intermediate;
    if (eventModeUsed || !token || strcmp(token, DECAY_GUID) != 0) return NULL;
    Instance *inst = (Instance *)calloc(1, sizeof(Instance));
    if (!inst) return NULL;
    decay_reset(&inst->model);
    inst->env = env;
    inst->log = log;
    strncpy(inst->name, name ? name : "", sizeof inst->name - 1);
    return inst;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String name, fmi3String token,
                                               fmi3String resources, fmi3Boolean visible,
                                               fmi3Boolean logging, fmi3InstanceEnvironment env,
                                               fmi3LogMessageCallback log,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lock,
                                               fmi3UnlockPreemptionCallback unlock) {
    (void)name, (void)token, (void)resources, (void)visible, (void)logging, (void)env,
        (void)log, (void)clockUpdate, (void)lock, (void)unlock;
    return NULL; /* co-simulation only */
}

void fmi3FreeInstance(fmi3Instance instance) { free(instance); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tolDefined,
                                       fmi3Float64 tol, fmi3Float64 start,
                                       fmi3Boolean stopDefined, fmi3Float64 stop) {
    Instance *inst = (Instance *)instance;
    (void)tolDefined, (void)tol, (void)stopDefined, (void)stop;
    inst->model.time = start;
    inst->model.phase = PHASE_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    ((Instance *)instance)->model.phase = PHASE_STEPPING;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) { UNSUPPORTED(fmi3EnterEventMode); }

fmi3Status fmi3Terminate(fmi3Instance instance) {
    ((Instance *)instance)->model.phase = PHASE_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    decay_reset(&((Instance *)instance)->model);
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                          fmi3Float64 values[], size_t nValues) {
    if (nValues != n) return fail(instance, "fmi3GetFloat64", "nValues != nValueReferences");
    for (size_t i = 0; i < n; i++)
        if (decay_get(&((Instance *)instance)->model, vr[i], &values[i]) != 0)
            return fail(instance, "fmi3GetFloat64", "unknown value reference");
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 values[], size_t nValues) {
    if (nValues != n) return fail(instance, "fmi3SetFloat64", "nValues != nValueReferences");
    for (size_t i = 0; i < n; i++) {
        const char *why = decay_set(&((Instance *)instance)->model, vr[i], values[i]);
        if (why) return fail(instance, "fmi3SetFloat64", why);
    }
    return fmi3OK;
}

/* the types the model does not have: an empty call is fine, anything else an error */
#define NO_TYPE(T)                                                                          \
    fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,   \
                          fmi3##T values[], size_t nValues) {                               \
        (void)vr, (void)values, (void)nValues;                                              \
        return n ? fail(instance, "fmi3Get" #T, "the model has no " #T " variables") : fmi3OK; \
    }                                                                                       \
    fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,   \
                          const fmi3##T values[], size_t nValues) {                         \
        (void)vr, (void)values, (void)nValues;                                              \
        return n ? fail(instance, "fmi3Set" #T, "the model has no " #T " variables") : fmi3OK; \
    }
NO_TYPE(Float32)
NO_TYPE(Int8)
NO_TYPE(UInt8)
NO_TYPE(Int16)
NO_TYPE(UInt16)
NO_TYPE(Int32)
NO_TYPE(UInt32)
NO_TYPE(Int64)
NO_TYPE(UInt64)
NO_TYPE(Boolean)
NO_TYPE(String)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                         size_t sizes[], fmi3Binary values[], size_t nValues) {
    (void)vr, (void)n, (void)sizes, (void)values, (void)nValues;
    UNSUPPORTED(fmi3GetBinary);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                         const size_t sizes[], const fmi3Binary values[], size_t nValues) {
    (void)vr, (void)n, (void)sizes, (void)values, (void)nValues;
    UNSUPPORTED(fmi3SetBinary);
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                        fmi3Clock values[]) {
    (void)vr, (void)n, (void)values;
    UNSUPPORTED(fmi3GetClock);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                        const fmi3Clock values[]) {
    (void)vr, (void)n, (void)values;
    UNSUPPORTED(fmi3SetClock);
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference vr,
                                               size_t *n) {
    (void)vr, (void)n;
    UNSUPPORTED(fmi3GetNumberOfVariableDependencies);
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementOfIndependents[],
                                       fmi3DependencyKind kinds[], size_t n) {
    (void)dependent, (void)elementOfDependent, (void)independents, (void)elementOfIndependents,
        (void)kinds, (void)n;
    UNSUPPORTED(fmi3GetVariableDependencies);
}

/* FMU state: a heap copy of the model struct */
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state) {
    if (!*state) *state = malloc(sizeof(Decay));
    if (!*state) return fail(instance, "fmi3GetFMUState", "out of memory");
    memcpy(*state, &((Instance *)instance)->model, sizeof(Decay));
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
    if (!state) return fail(instance, "fmi3SetFMUState", "no state");
    memcpy(&((Instance *)instance)->model, state, sizeof(Decay));
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state) {
    (void)instance;
    free(*state);
    *state = NULL;
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size) {
    (void)instance, (void)state;
    *size = sizeof(Decay);
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[],
                                 size_t size) {
    if (size != sizeof(Decay)) return fail(instance, "fmi3SerializeFMUState", "wrong size");
    memcpy(bytes, state, sizeof(Decay));
    return fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size,
                                   fmi3FMUState *state) {
    if (size != sizeof(Decay)) return fail(instance, "fmi3DeserializeFMUState", "wrong size");
    if (!*state) *state = malloc(sizeof(Decay));
    if (!*state) return fail(instance, "fmi3DeserializeFMUState", "out of memory");
    memcpy(*state, bytes, sizeof(Decay));
    return fmi3OK;
}

#define NO_DERIVATIVE(NAME)                                                                 \
    fmi3Status NAME(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nu,  \
                    const fmi3ValueReference knowns[], size_t nk, const fmi3Float64 seed[], \
                    size_t ns, fmi3Float64 sensitivity[], size_t nsens) {                   \
        (void)unknowns, (void)nu, (void)knowns, (void)nk, (void)seed, (void)ns,            \
            (void)sensitivity, (void)nsens;                                                 \
        UNSUPPORTED(NAME);                                                                  \
    }
NO_DERIVATIVE(fmi3GetDirectionalDerivative)
NO_DERIVATIVE(fmi3GetAdjointDerivative)

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterConfigurationMode);
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3ExitConfigurationMode);
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier q[]) {
    (void)vr, (void)n, (void)intervals, (void)q;
    UNSUPPORTED(fmi3GetIntervalDecimal);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[],
                                   size_t n, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier q[]) {
    (void)vr, (void)n, (void)counters, (void)resolutions, (void)q;
    UNSUPPORTED(fmi3GetIntervalFraction);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                               fmi3Float64 shifts[]) {
    (void)vr, (void)n, (void)shifts;
    UNSUPPORTED(fmi3GetShiftDecimal);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[]) {
    (void)vr, (void)n, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3GetShiftFraction);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Float64 intervals[]) {
    (void)vr, (void)n, (void)intervals;
    UNSUPPORTED(fmi3SetIntervalDecimal);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[],
                                   size_t n, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[]) {
    (void)vr, (void)n, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetIntervalFraction);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                               const fmi3Float64 shifts[]) {
    (void)vr, (void)n, (void)shifts;
    UNSUPPORTED(fmi3SetShiftDecimal);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
    (void)vr, (void)n, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetShiftFraction);
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    UNSUPPORTED(fmi3EvaluateDiscreteStates);
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *needUpdate,
                                    fmi3Boolean *terminate, fmi3Boolean *nominalsChanged,
                                    fmi3Boolean *valuesChanged, fmi3Boolean *nextDefined,
                                    fmi3Float64 *next) {
    (void)needUpdate, (void)terminate, (void)nominalsChanged, (void)valuesChanged,
        (void)nextDefined, (void)next;
    UNSUPPORTED(fmi3UpdateDiscreteStates);
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterContinuousTimeMode);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetPrior,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminate) {
    (void)noSetPrior, (void)enterEventMode, (void)terminate;
    UNSUPPORTED(fmi3CompletedIntegratorStep);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    (void)time;
    UNSUPPORTED(fmi3SetTime);
}

#define NO_STATE_VECTOR(NAME, CONST)                                                  \
    fmi3Status NAME(fmi3Instance instance, CONST fmi3Float64 values[], size_t n) {    \
        (void)values, (void)n;                                                        \
        UNSUPPORTED(NAME);                                                            \
    }
NO_STATE_VECTOR(fmi3SetContinuousStates, const)
NO_STATE_VECTOR(fmi3GetContinuousStateDerivatives, )
NO_STATE_VECTOR(fmi3GetEventIndicators, )
NO_STATE_VECTOR(fmi3GetContinuousStates, )
NO_STATE_VECTOR(fmi3GetNominalsOfContinuousStates, )

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n) {
    (void)n;
    UNSUPPORTED(fmi3GetNumberOfEventIndicators);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n) {
    (void)n;
    UNSUPPORTED(fmi3GetNumberOfContinuousStates);
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) { UNSUPPORTED(fmi3EnterStepMode); }

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[],
                                    size_t n, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    (void)vr, (void)n, (void)orders, (void)values, (void)nValues;
    UNSUPPORTED(fmi3GetOutputDerivatives);
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 t, fmi3Float64 h,
                      fmi3Boolean noSetPrior, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime) {
    Instance *inst = (Instance *)instance;
    (void)t, (void)noSetPrior;
    if (inst->model.phase != PHASE_STEPPING) return fail(instance, "fmi3DoStep", "not initialized");
    if (!(h >= 0.0)) return fail(instance, "fmi3DoStep", "negative step");
    decay_step(&inst->model, h);
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    *lastSuccessfulTime = inst->model.time;
    return fmi3OK;
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clock,
                                      fmi3Float64 time) {
    (void)clock, (void)time;
    UNSUPPORTED(fmi3ActivateModelPartition);
}
