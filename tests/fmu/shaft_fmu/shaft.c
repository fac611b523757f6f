/* A test FMU (FMI 2.0 co-simulation): a compliant shaft between a flange (inputs: its angle and
 * speed, from the FMU it drives) and an end inertia J (a motor or a load: a constant torque
 * T_e and a viscous torque -c w_e act on it). Output: the shaft's torque on the flange,
 *
 *   tau = k (phi_e - phi_f) + d (w_e - w_f),   J w_e' = T_e - c w_e - tau,
 *
 * the flange moving at its input speed over a step (phi_f = phi_f0 + w_f0 (t - t0)); the end
 * inertia is stepped by 64 classical Runge-Kutta substeps per communication step. Used by
 * tests/fmu/test_native_drive.py to connect the gear FMU's drivetrain interface between two
 * shafts in libcosim. C99, libm only. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

enum { VR_PHI_F = 1, VR_W_F, VR_TAU, VR_PHI_E, VR_W_E, VR_K, VR_D, VR_J, VR_TE, VR_C,
       VR_PHI0, VR_W0, N_VR };

typedef struct {
    double v[N_VR];   /* by value reference */
    double t;
} shaft;

static double torque(const shaft *s, double phi_f, double w_f, double phi_e, double w_e)
{
    return s->v[VR_K] * (phi_e - phi_f) + s->v[VR_D] * (w_e - w_f);
}

static void rhs(const shaft *s, double tt, const double *y, double *dy)
{
    double phi_f = s->v[VR_PHI_F] + s->v[VR_W_F] * tt;
    dy[0] = y[1];
    dy[1] = (s->v[VR_TE] - s->v[VR_C] * y[1] - torque(s, phi_f, s->v[VR_W_F], y[0], y[1]))
        / s->v[VR_J];
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String x[])
{ (void)c; (void)on; (void)n; (void)x; return fmi2OK; }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *cb,
                              fmi2Boolean visible, fmi2Boolean logging)
{
    shaft *s;
    (void)name; (void)location; (void)cb; (void)visible; (void)logging;
    if (type != fmi2CoSimulation || !guid || strcmp(guid, "{gear-dyn-test-shaft-1}")) return NULL;
    s = (shaft *)calloc(1, sizeof *s);
    if (!s) return NULL;
    s->v[VR_K] = 1e3; s->v[VR_D] = 1.0; s->v[VR_J] = 1.0;
    return s;
}

void fmi2FreeInstance(fmi2Component c) { free(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean a, fmi2Real b, fmi2Real t0,
                               fmi2Boolean d, fmi2Real e)
{ (void)a; (void)b; (void)d; (void)e; ((shaft *)c)->t = t0; return fmi2OK; }
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    shaft *s = (shaft *)c;
    s->v[VR_PHI_E] = s->v[VR_PHI0];
    s->v[VR_W_E] = s->v[VR_W0];
    return fmi2OK;
}
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { (void)c; return fmi2Error; }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[])
{
    shaft *s = (shaft *)c;
    size_t k;
    for (k = 0; k < n; k++) {
        if (vr[k] < 1 || vr[k] >= N_VR) return fmi2Error;
        v[k] = vr[k] == VR_TAU ? torque(s, s->v[VR_PHI_F], s->v[VR_W_F], s->v[VR_PHI_E],
                                        s->v[VR_W_E]) : s->v[vr[k]];
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real v[])
{
    size_t k;
    for (k = 0; k < n; k++) {
        if (vr[k] < 1 || vr[k] >= N_VR || vr[k] == VR_TAU) return fmi2Error;
        ((shaft *)c)->v[vr[k]] = v[k];
        /* the start state at once: a host reads the torque in initialization mode */
        if (vr[k] == VR_PHI0) ((shaft *)c)->v[VR_PHI_E] = v[k];
        if (vr[k] == VR_W0) ((shaft *)c)->v[VR_W_E] = v[k];
    }
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_prior)
{
    shaft *s = (shaft *)c;
    double y[2] = {s->v[VR_PHI_E], s->v[VR_W_E]}, k1[2], k2[2], k3[2], k4[2], yt[2];
    double dt = h / 64.0, tt = 0.0;
    int i, j;
    (void)no_prior;
    if (!(h > 0.0) || t != s->t) return fmi2Error;
    for (i = 0; i < 64; i++, tt += dt) {
        rhs(s, tt, y, k1);
        for (j = 0; j < 2; j++) yt[j] = y[j] + 0.5 * dt * k1[j];
        rhs(s, tt + 0.5 * dt, yt, k2);
        for (j = 0; j < 2; j++) yt[j] = y[j] + 0.5 * dt * k2[j];
        rhs(s, tt + 0.5 * dt, yt, k3);
        for (j = 0; j < 2; j++) yt[j] = y[j] + dt * k3[j];
        rhs(s, tt + dt, yt, k4);
        for (j = 0; j < 2; j++) y[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
    s->v[VR_PHI_E] = y[0];
    s->v[VR_W_E] = y[1];
    s->v[VR_PHI_F] += s->v[VR_W_F] * h;   /* the flange where the hold puts it; the host
                                              sets the true one before the next step */
    s->t = t + h;
    return fmi2OK;
}

/* what this test FMU does not provide */
#define NONE(T) \
    fmi2Status fmi2Get##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2##T v[]) \
    { (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK; } \
    fmi2Status fmi2Set##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, \
                          const fmi2##T v[]) \
    { (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK; }
NONE(Integer)
NONE(Boolean)
NONE(String)
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)c; (void)s; return fmi2Error; }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { (void)c; (void)s; return fmi2Error; }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)c; (void)s; return fmi2Error; }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n)
{ (void)c; (void)s; (void)n; return fmi2Error; }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n)
{ (void)c; (void)s; (void)b; (void)n; return fmi2Error; }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n,
                                   fmi2FMUstate *s)
{ (void)c; (void)s; (void)b; (void)n; return fmi2Error; }
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real du[], fmi2Real dz[])
{ (void)c; (void)u; (void)nu; (void)z; (void)nz; (void)du; (void)dz; return fmi2Error; }
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer o[], const fmi2Real v[])
{ (void)c; (void)vr; (void)n; (void)o; (void)v; return fmi2Error; }
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer o[], fmi2Real v[])
{ (void)c; (void)vr; (void)n; (void)o; (void)v; return fmi2Error; }
fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }
#define STATUS(T, V) \
    fmi2Status fmi2Get##T##Status(fmi2Component c, const fmi2StatusKind k, fmi2##V *v) \
    { (void)c; (void)k; (void)v; return fmi2Discard; }
STATUS(, Status)
STATUS(Real, Real)
STATUS(Integer, Integer)
STATUS(Boolean, Boolean)
STATUS(String, String)
