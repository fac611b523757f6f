/* FMI 3.0 co-simulation glue of the gear_dyn native kernel (gd_kernel.h); the same value
 * references and the same kernel calls as the FMI 2.0 glue (gd_fmi2.c). Model exchange and
 * scheduled execution are not provided: their functions exist (the standard header declares
 * them) and return fmi3Error. */
#include <stdlib.h>
#include <string.h>
#include "fmi3/fmi3Functions.h"
#include "gd_glue.h"

typedef struct {
    gd_dstate st;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    int started, mode;   /* started: fixed parameters locked; mode: GD_INSTANTIATED .. */
} inst;

#define M (&gd_model_data)
#define I ((inst *)c)

static fmi3Status fail(inst *c, const char *msg)
{
    if (c->log) c->log(c->env, fmi3Error, "logStatusError", msg);
    return fmi3Error;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n, const fmi3String cat[])
{
    (void)c; (void)on; (void)n; (void)cat;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
    fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early_return,
    const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update)
{
    inst *c;
    const char *bad = event_mode ? "event mode is not supported"
        : M->format != GD_TABLE_FORMAT ? "model_data.c has another table format than the kernel"
        : !gd_token_ok(token) ? "the instantiationToken is not this FMU's (see its "
                                "modelDescription.xml)"
        : NULL;
    (void)name; (void)resources; (void)visible; (void)logging;
    (void)early_return; (void)required; (void)n_required; (void)update;
    if (bad) {
        if (log) log(env, fmi3Error, "logStatusError", bad);
        return NULL;
    }
    c = (inst *)calloc(1, sizeof *c);
    if (!c) return NULL;
    c->env = env;
    c->log = log;
    gd_g_defaults(&c->st);
    return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String res,
                                          fmi3Boolean visible, fmi3Boolean logging,
                                          fmi3InstanceEnvironment env, fmi3LogMessageCallback log)
{
    (void)name; (void)token; (void)res; (void)visible; (void)logging; (void)env; (void)log;
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String name, fmi3String token, fmi3String res, fmi3Boolean visible, fmi3Boolean logging,
    fmi3InstanceEnvironment env, fmi3LogMessageCallback log, fmi3ClockUpdateCallback clock,
    fmi3LockPreemptionCallback lock, fmi3UnlockPreemptionCallback unlock)
{
    (void)name; (void)token; (void)res; (void)visible; (void)logging; (void)env; (void)log;
    (void)clock; (void)lock; (void)unlock;
    return NULL;
}

void fmi3FreeInstance(fmi3Instance c) { free(c); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tol_on, fmi3Float64 tol,
                                       fmi3Float64 t0, fmi3Boolean stop_on, fmi3Float64 stop)
{
    (void)tol_on; (void)tol; (void)stop_on; (void)stop;
    if (I->mode != GD_INSTANTIATED)
        return fail(I, "fmi3EnterInitializationMode: allowed only after instantiation or "
                    "fmi3Reset");
    if (!(t0 == t0 && t0 - t0 == 0.0))
        return fail(I, "fmi3EnterInitializationMode: the start time must be finite");
    I->st.k.t = t0;
    I->mode = GD_INIT;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance c)
{
    if (I->mode != GD_INIT)
        return fail(I, "fmi3ExitInitializationMode: not in initialization mode");
    gd_g_start(&I->st, I->st.k.t);
    I->started = 1;
    I->mode = GD_STEP;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance c)
{
    I->mode = GD_TERMINATED;   /* also after a failed initialization */
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance c)
{
    gd_g_defaults(&I->st);
    I->started = 0;
    I->mode = GD_INSTANTIATED;
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                          fmi3Float64 v[], size_t nv)
{
    if (nv != n || gd_g_read(&I->st, I->mode, vr, n, v) != GD_OK)
        return fail(I, "fmi3GetFloat64: unknown value reference");
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 v[], size_t nv)
{
    char msg[256];
    size_t k;
    if (nv != n) return fail(I, "fmi3SetFloat64: one value per value reference");
    for (k = 0; k < n; k++)
        if (gd_g_set(&I->st, vr[k], v[k], I->started, msg, sizeof msg) != GD_OK)
            return fail(I, msg);
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_prior,
                      fmi3Boolean *event, fmi3Boolean *terminate, fmi3Boolean *early,
                      fmi3Float64 *last)
{
    char msg[320];
    int rc;
    (void)no_prior;
    *event = fmi3False;
    *terminate = fmi3False;
    *early = fmi3False;
    *last = I->st.k.t;
    if (gd_check_step(I->mode, &I->st.k, t, h, "fmi3DoStep", msg, sizeof msg) != GD_OK)
        return fail(I, msg);
    rc = gd_g_advance(&I->st, t + h);
    *last = I->st.k.t;
    return rc == GD_OK ? fmi3OK : fail(I, GD_STEP_MESSAGE);
}

/* the FMU state: the kernel's state behind a header naming this FMU (gd_saved, gd_glue.h);
 * a state handed in is validated before use */
fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState *s)
{
    if (!*s) *s = malloc(sizeof(gd_saved));
    if (!*s) return fail(I, "fmi3GetFMUState: out of memory");
    gd_save(&I->st, I->mode, (gd_saved *)*s);
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState s)
{
    char msg[256];
    if (gd_check_saved(s, sizeof(gd_saved), M, "fmi3SetFMUState", &I->st, &I->mode, msg,
                       sizeof msg) != GD_OK)
        return fail(I, msg);
    I->started = I->mode >= GD_STEP;
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState *s)
{
    (void)c;
    free(*s);
    *s = NULL;
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState s, size_t *size)
{
    (void)c; (void)s;
    *size = sizeof(gd_saved);
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState s, fmi3Byte b[], size_t size)
{
    char msg[256];
    if (gd_check_saved(s, size, M, "fmi3SerializeFMUState", NULL, NULL, msg, sizeof msg)
        != GD_OK)
        return fail(I, msg);
    memcpy(b, s, size);
    return fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte b[], size_t size,
                                   fmi3FMUState *s)
{
    char msg[256];
    if (gd_check_saved(b, size, M, "fmi3DeserializeFMUState", NULL, NULL, msg, sizeof msg)
        != GD_OK)
        return fail(I, msg);
    if (!(*s = malloc(sizeof(gd_saved))))
        return fail(I, "fmi3DeserializeFMUState: out of memory");
    memcpy(*s, b, size);
    return fmi3OK;
}

/* ---- what this FMU does not provide: fmi3Error (or no values for n = 0) */
#define VR_ARGS fmi3Instance c, const fmi3ValueReference vr[], size_t n
#define UNUSED_VR (void)c; (void)vr
#define NO_TYPE(T) \
    fmi3Status fmi3Get##T(VR_ARGS, fmi3##T v[], size_t nv) \
    { UNUSED_VR; (void)v; (void)nv; return n ? fmi3Error : fmi3OK; } \
    fmi3Status fmi3Set##T(VR_ARGS, const fmi3##T v[], size_t nv) \
    { UNUSED_VR; (void)v; (void)nv; return n ? fmi3Error : fmi3OK; }
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

fmi3Status fmi3GetBinary(VR_ARGS, size_t sizes[], fmi3Binary v[], size_t nv)
{ UNUSED_VR; (void)sizes; (void)v; (void)nv; return n ? fmi3Error : fmi3OK; }
fmi3Status fmi3SetBinary(VR_ARGS, const size_t sizes[], const fmi3Binary v[], size_t nv)
{ UNUSED_VR; (void)sizes; (void)v; (void)nv; return n ? fmi3Error : fmi3OK; }
fmi3Status fmi3GetClock(VR_ARGS, fmi3Clock v[])
{ UNUSED_VR; (void)v; return n ? fmi3Error : fmi3OK; }
fmi3Status fmi3SetClock(VR_ARGS, const fmi3Clock v[])
{ UNUSED_VR; (void)v; return n ? fmi3Error : fmi3OK; }
fmi3Status fmi3GetIntervalDecimal(VR_ARGS, fmi3Float64 v[], fmi3IntervalQualifier q[])
{ UNUSED_VR; (void)n; (void)v; (void)q; return fmi3Error; }
fmi3Status fmi3GetIntervalFraction(VR_ARGS, fmi3UInt64 a[], fmi3UInt64 b[],
                                   fmi3IntervalQualifier q[])
{ UNUSED_VR; (void)n; (void)a; (void)b; (void)q; return fmi3Error; }
fmi3Status fmi3GetShiftDecimal(VR_ARGS, fmi3Float64 v[])
{ UNUSED_VR; (void)n; (void)v; return fmi3Error; }
fmi3Status fmi3GetShiftFraction(VR_ARGS, fmi3UInt64 a[], fmi3UInt64 b[])
{ UNUSED_VR; (void)n; (void)a; (void)b; return fmi3Error; }
fmi3Status fmi3SetIntervalDecimal(VR_ARGS, const fmi3Float64 v[])
{ UNUSED_VR; (void)n; (void)v; return fmi3Error; }
fmi3Status fmi3SetIntervalFraction(VR_ARGS, const fmi3UInt64 a[], const fmi3UInt64 b[])
{ UNUSED_VR; (void)n; (void)a; (void)b; return fmi3Error; }
fmi3Status fmi3SetShiftDecimal(VR_ARGS, const fmi3Float64 v[])
{ UNUSED_VR; (void)n; (void)v; return fmi3Error; }
fmi3Status fmi3SetShiftFraction(VR_ARGS, const fmi3UInt64 a[], const fmi3UInt64 b[])
{ UNUSED_VR; (void)n; (void)a; (void)b; return fmi3Error; }
fmi3Status fmi3GetOutputDerivatives(VR_ARGS, const fmi3Int32 o[], fmi3Float64 v[], size_t nv)
{ UNUSED_VR; (void)n; (void)o; (void)v; (void)nv; return fmi3Error; }

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance c, fmi3ValueReference vr,
                                               size_t *n)
{ (void)c; (void)vr; (void)n; return fmi3Error; }
fmi3Status fmi3GetVariableDependencies(fmi3Instance c, fmi3ValueReference vr, size_t a[],
                                       fmi3ValueReference b[], size_t d[],
                                       fmi3DependencyKind k[], size_t n)
{ (void)c; (void)vr; (void)a; (void)b; (void)d; (void)k; (void)n; return fmi3Error; }

#define DERIV(NAME) \
    fmi3Status NAME(fmi3Instance c, const fmi3ValueReference u[], size_t nu, \
                    const fmi3ValueReference k[], size_t nk, const fmi3Float64 seed[], \
                    size_t ns, fmi3Float64 out[], size_t no) \
    { (void)c; (void)u; (void)nu; (void)k; (void)nk; (void)seed; (void)ns; (void)out; \
      (void)no; return fmi3Error; }
DERIV(fmi3GetDirectionalDerivative)
DERIV(fmi3GetAdjointDerivative)

#define NO_MODE(NAME) fmi3Status NAME(fmi3Instance c) { (void)c; return fmi3Error; }
NO_MODE(fmi3EnterConfigurationMode)
NO_MODE(fmi3ExitConfigurationMode)
NO_MODE(fmi3EnterEventMode)
NO_MODE(fmi3EvaluateDiscreteStates)
NO_MODE(fmi3EnterContinuousTimeMode)
NO_MODE(fmi3EnterStepMode)

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean *a, fmi3Boolean *b,
                                    fmi3Boolean *d, fmi3Boolean *e, fmi3Boolean *f,
                                    fmi3Float64 *t)
{ (void)c; (void)a; (void)b; (void)d; (void)e; (void)f; (void)t; return fmi3Error; }
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean no_prior, fmi3Boolean *a,
                                       fmi3Boolean *b)
{ (void)c; (void)no_prior; (void)a; (void)b; return fmi3Error; }
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 t) { (void)c; (void)t; return fmi3Error; }

#define ARRAY(NAME, Q) \
    fmi3Status NAME(fmi3Instance c, Q fmi3Float64 v[], size_t n) \
    { (void)c; (void)v; (void)n; return fmi3Error; }
ARRAY(fmi3SetContinuousStates, const)
ARRAY(fmi3GetContinuousStateDerivatives, )
ARRAY(fmi3GetEventIndicators, )
ARRAY(fmi3GetContinuousStates, )
ARRAY(fmi3GetNominalsOfContinuousStates, )

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t *n)
{ (void)c; *n = 0; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t *n)
{ (void)c; *n = 0; return fmi3OK; }
fmi3Status fmi3ActivateModelPartition(fmi3Instance c, fmi3ValueReference vr, fmi3Float64 t)
{ (void)c; (void)vr; (void)t; return fmi3Error; }
