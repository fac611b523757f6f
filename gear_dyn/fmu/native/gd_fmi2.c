/* FMI 2.0 co-simulation glue of the gear_dyn native kernel (gd_kernel.h). Value references:
 * 1..5 the parameters and inputs (GD_SPEED..GD_TOL), 6..11 the outputs (GD_X..GD_DRIVEN). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2/fmi2Functions.h"
#include "gd_glue.h"

typedef struct {
    gd_dstate st;
    fmi2CallbackFunctions cb;
    char name[128];
    int started, mode;   /* started: fixed parameters locked; mode: GD_INSTANTIATED .. */
} inst;

#define M (&gd_model_data)

static void logmsg(inst *c, fmi2Status status, const char *msg)
{
    if (c->cb.logger) c->cb.logger(c->cb.componentEnvironment, c->name, status, "logError", msg);
}

static fmi2Status fail(inst *c, const char *msg)
{
    logmsg(c, fmi2Error, msg);
    return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cat[])
{
    (void)c; (void)on; (void)n; (void)cat;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *cb,
                              fmi2Boolean visible, fmi2Boolean logging)
{
    inst *c;
    const char *bad = type != fmi2CoSimulation ? "this FMU supports co-simulation only"
        : M->format != GD_TABLE_FORMAT ? "model_data.c has another table format than the kernel"
        : !gd_token_ok(guid) ? "the guid is not this FMU's (see its modelDescription.xml)"
        : NULL;
    (void)location; (void)visible; (void)logging;
    if (bad) {
        if (cb && cb->logger)
            cb->logger(cb->componentEnvironment, name ? name : "gear_dyn", fmi2Error, "logError",
                       bad);
        return NULL;
    }
    c = (inst *)calloc(1, sizeof *c);
    if (!c) return NULL;
    if (cb) c->cb = *cb;
    strncpy(c->name, name ? name : "gear_dyn", sizeof c->name - 1);
    gd_g_defaults(&c->st);
    return c;
}

void fmi2FreeInstance(fmi2Component c) { free(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_on, fmi2Real tol,
                               fmi2Real t0, fmi2Boolean stop_on, fmi2Real stop)
{
    inst *i = (inst *)c;
    (void)tol_on; (void)tol; (void)stop_on; (void)stop;
    if (i->mode != GD_INSTANTIATED)
        return fail(i, "fmi2SetupExperiment: allowed only after fmi2Instantiate or fmi2Reset");
    if (!(t0 == t0 && t0 - t0 == 0.0))
        return fail(i, "fmi2SetupExperiment: the start time must be finite");
    i->st.k.t = t0;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    inst *i = (inst *)c;
    if (i->mode != GD_INSTANTIATED)
        return fail(i, "fmi2EnterInitializationMode: allowed only after fmi2Instantiate or "
                    "fmi2Reset");
    i->mode = GD_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    inst *i = (inst *)c;
    if (i->mode != GD_INIT)
        return fail(i, "fmi2ExitInitializationMode: not in initialization mode");
    gd_g_start(&i->st, i->st.k.t);
    i->started = 1;
    i->mode = GD_STEP;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    ((inst *)c)->mode = GD_TERMINATED;   /* also after a failed initialization */
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    inst *i = (inst *)c;
    gd_g_defaults(&i->st);
    i->started = 0;
    i->mode = GD_INSTANTIATED;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[])
{
    if (gd_g_read(&((inst *)c)->st, ((inst *)c)->mode, vr, n, v) != GD_OK)
        return fail((inst *)c, "fmi2GetReal: unknown value reference");
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real v[])
{
    inst *i = (inst *)c;
    char msg[256];
    size_t k;
    for (k = 0; k < n; k++)
        if (gd_g_set(&i->st, vr[k], v[k], i->started, msg, sizeof msg) != GD_OK) {
            logmsg(i, fmi2Error, msg);
            return fmi2Error;
        }
    return fmi2OK;
}

#define NOT_USED(T) \
    fmi2Status fmi2Get##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2##T v[]) \
    { (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK; } \
    fmi2Status fmi2Set##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, \
                          const fmi2##T v[]) \
    { (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK; }
NOT_USED(Integer)
NOT_USED(Boolean)
NOT_USED(String)

/* the FMU state: the kernel's state behind a header naming this FMU (gd_saved, gd_glue.h);
 * a state handed in is validated before use */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    if (!*s) *s = malloc(sizeof(gd_saved));
    if (!*s) return fail((inst *)c, "fmi2GetFMUstate: out of memory");
    gd_save(&((inst *)c)->st, ((inst *)c)->mode, (gd_saved *)*s);
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    inst *i = (inst *)c;
    char msg[256];
    if (gd_check_saved(s, sizeof(gd_saved), M, "fmi2SetFMUstate", &i->st, &i->mode, msg,
                       sizeof msg) != GD_OK)
        return fail(i, msg);
    i->started = i->mode >= GD_STEP;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)c;
    free(*s);
    *s = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    (void)c; (void)s;
    *size = sizeof(gd_saved);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t size)
{
    char msg[256];
    if (gd_check_saved(s, size, M, "fmi2SerializeFMUstate", NULL, NULL, msg, sizeof msg)
        != GD_OK)
        return fail((inst *)c, msg);
    memcpy(b, s, size);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t size,
                                   fmi2FMUstate *s)
{
    char msg[256];
    if (gd_check_saved(b, size, M, "fmi2DeSerializeFMUstate", NULL, NULL, msg, sizeof msg)
        != GD_OK)
        return fail((inst *)c, msg);
    if (!(*s = malloc(sizeof(gd_saved))))
        return fail((inst *)c, "fmi2DeSerializeFMUstate: out of memory");
    memcpy(*s, b, size);
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real du[], fmi2Real dz[])
{
    (void)c; (void)u; (void)nu; (void)z; (void)nz; (void)du; (void)dz;
    return fmi2Error;
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[])
{
    (void)c; (void)vr; (void)n; (void)order; (void)v;
    return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[])
{
    (void)c; (void)vr; (void)n; (void)order; (void)v;
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_prior)
{
    inst *i = (inst *)c;
    char msg[320];
    (void)no_prior;
    if (gd_check_step(i->mode, &i->st.k, t, h, "fmi2DoStep", msg, sizeof msg) != GD_OK)
        return fail(i, msg);
    if (gd_g_advance(&i->st, t + h) == GD_OK) return fmi2OK;
    return fail(i, GD_STEP_MESSAGE);
}

fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }

#define STATUS(T, V) \
    fmi2Status fmi2Get##T##Status(fmi2Component c, const fmi2StatusKind k, fmi2##V *v) \
    { (void)c; (void)k; (void)v; return fmi2Discard; }
STATUS(, Status)
STATUS(Real, Real)
STATUS(Integer, Integer)
STATUS(Boolean, Boolean)
STATUS(String, String)
