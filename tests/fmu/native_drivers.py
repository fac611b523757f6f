"""C drivers of the native FMU under AddressSanitizer and UBSan (tests/fmu/test_native_kernel.py
and test_native_torsional.py): instantiate, refuse an out-of-range damping ratio, reset, step
400 times at a step that does not divide the mesh period, copy the state at step 100, serialize,
deserialize and restore it, read two outputs. Only the value references and the step differ
between the models.

On the way every call the standard forbids must give Error (else the driver exits 5, naming the
line on stderr): instantiation with another token, doStep before initialization, with a step
that is zero, negative, NaN or infinite, from another time than the FMU's and after terminate;
a serialized state of the wrong size, magic number, version or token, with a table piece out of
range or a NaN in it (deserialize and set).
"""

from __future__ import annotations

_FMI2 = r"""
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "fmi2/fmi2Functions.h"
#include "gd_glue.h"
#define REFUSED(call) \
    if ((call) != fmi2Error) { fprintf(stderr, "line %%d: not refused\n", __LINE__); return 5; }
static void lg(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c,
               fmi2String m, ...) { (void)e; (void)n; (void)s; (void)c; (void)m; }
int main(void) {
    fmi2CallbackFunctions cb = {lg, 0, 0, 0, 0};
    fmi2ValueReference vr[2] = {%(out0)d, %(out1)d}, zeta = 3;
    fmi2Real v[2], bad = 50.0, t = 0.0, h = %(step)s;
    fmi2FMUstate s = 0, s2 = 0;
    fmi2Byte buf[4096];
    size_t size = 0;
    int i;
    gd_saved sv;
    fmi2Component c = fmi2Instantiate("a", fmi2CoSimulation, "{other}", "", &cb, 0, 0);
    if (c) return 5;
    c = fmi2Instantiate("a", fmi2CoSimulation, gd_instantiation_token, "", &cb, 0, 0);
    if (!c || fmi2SetReal(c, &zeta, 1, &bad) != fmi2Error) return 2;
    fmi2Reset(c);
    REFUSED(fmi2DoStep(c, 0.0, h, 1));
    fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
    fmi2EnterInitializationMode(c);
    REFUSED(fmi2DoStep(c, 0.0, h, 1));
    fmi2ExitInitializationMode(c);
    REFUSED(fmi2DoStep(c, 0.0, 0.0, 1));
    REFUSED(fmi2DoStep(c, 0.0, -h, 1));
    REFUSED(fmi2DoStep(c, 0.0, NAN, 1));
    REFUSED(fmi2DoStep(c, 0.0, HUGE_VAL, 1));
    REFUSED(fmi2DoStep(c, 5.0 * h, h, 1));
    for (i = 0; i < 400; i++, t += h) {
        if (fmi2DoStep(c, t, h, 1) != fmi2OK) return 3;
        if (i == 100) fmi2GetFMUstate(c, &s);
    }
    if (fmi2SerializedFMUstateSize(c, s, &size) != fmi2OK || size != sizeof sv) return 4;
    fmi2SerializeFMUstate(c, s, buf, size);
    REFUSED(fmi2DeSerializeFMUstate(c, buf, size - 1, &s2));
    memcpy(&sv, buf, size); sv.magic ^= 1u;
    REFUSED(fmi2DeSerializeFMUstate(c, (fmi2Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.version += 1u;
    REFUSED(fmi2DeSerializeFMUstate(c, (fmi2Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.token[0] ^= 'x';
    REFUSED(fmi2DeSerializeFMUstate(c, (fmi2Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.st.k.piece = 1000000;
    REFUSED(fmi2DeSerializeFMUstate(c, (fmi2Byte *)&sv, size, &s2));
    REFUSED(fmi2SetFMUstate(c, &sv));
    memcpy(&sv, buf, size); sv.st.k.q[2] = NAN; sv.st.k.x = NAN;
    REFUSED(fmi2SetFMUstate(c, &sv));
    fmi2DeSerializeFMUstate(c, buf, size, &s2);
    fmi2SetFMUstate(c, s2);
    fmi2FreeFMUstate(c, &s);
    fmi2FreeFMUstate(c, &s2);
    fmi2GetReal(c, vr, 2, v);
    printf("%%.17g %%.17g\n", v[0], v[1]);
    fmi2Terminate(c);
    REFUSED(fmi2DoStep(c, t, h, 1));
    fmi2FreeInstance(c);
    return 0;
}
"""

_FMI3 = r"""
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "fmi3/fmi3Functions.h"
#include "gd_glue.h"
#define REFUSED(call) \
    if ((call) != fmi3Error) { fprintf(stderr, "line %%d: not refused\n", __LINE__); return 5; }
#define STEP(t, h) fmi3DoStep(c, t, h, 1, &ev, &term, &early, &last)
static void lg(fmi3InstanceEnvironment e, fmi3Status s, fmi3String c, fmi3String m)
{ (void)e; (void)s; (void)c; (void)m; }
int main(void) {
    fmi3ValueReference vr[2] = {%(out0)d, %(out1)d}, zeta = 3;
    fmi3Float64 v[2], bad = 50.0, t = 0.0, h = %(step)s, last;
    fmi3Boolean ev, term, early;
    fmi3FMUState s = 0, s2 = 0;
    fmi3Byte buf[4096];
    size_t size = 0;
    int i;
    gd_saved sv;
    fmi3Instance c = fmi3InstantiateCoSimulation("a", "{other}", "", 0, 1, 0, 0, 0, 0, 0, lg, 0);
    if (c) return 5;
    c = fmi3InstantiateCoSimulation("a", gd_instantiation_token, "", 0, 1, 0, 0, 0, 0, 0, lg, 0);
    if (!c || fmi3SetFloat64(c, &zeta, 1, &bad, 1) != fmi3Error) return 2;
    fmi3Reset(c);
    REFUSED(STEP(0.0, h));
    fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0);
    REFUSED(STEP(0.0, h));
    fmi3ExitInitializationMode(c);
    REFUSED(STEP(0.0, 0.0));
    REFUSED(STEP(0.0, -h));
    REFUSED(STEP(0.0, NAN));
    REFUSED(STEP(0.0, HUGE_VAL));
    REFUSED(STEP(5.0 * h, h));
    for (i = 0; i < 400; i++, t += h) {
        if (STEP(t, h) != fmi3OK) return 3;
        if (i == 100) fmi3GetFMUState(c, &s);
    }
    if (fmi3SerializedFMUStateSize(c, s, &size) != fmi3OK || size != sizeof sv) return 4;
    fmi3SerializeFMUState(c, s, buf, size);
    REFUSED(fmi3DeserializeFMUState(c, buf, size - 1, &s2));
    memcpy(&sv, buf, size); sv.magic ^= 1u;
    REFUSED(fmi3DeserializeFMUState(c, (fmi3Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.version += 1u;
    REFUSED(fmi3DeserializeFMUState(c, (fmi3Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.token[0] ^= 'x';
    REFUSED(fmi3DeserializeFMUState(c, (fmi3Byte *)&sv, size, &s2));
    memcpy(&sv, buf, size); sv.st.k.piece = 1000000;
    REFUSED(fmi3DeserializeFMUState(c, (fmi3Byte *)&sv, size, &s2));
    REFUSED(fmi3SetFMUState(c, &sv));
    memcpy(&sv, buf, size); sv.st.k.q[2] = NAN; sv.st.k.x = NAN;
    REFUSED(fmi3SetFMUState(c, &sv));
    fmi3DeserializeFMUState(c, buf, size, &s2);
    fmi3SetFMUState(c, s2);
    fmi3FreeFMUState(c, &s);
    fmi3FreeFMUState(c, &s2);
    fmi3GetFloat64(c, vr, 2, v, 2);
    printf("%%.17g %%.17g\n", v[0], v[1]);
    fmi3Terminate(c);
    REFUSED(STEP(t, h));
    fmi3FreeInstance(c);
    return 0;
}
"""


def driver(fmi: int, outputs: tuple[int, int], step: str) -> str:
    """The C source of the driver for FMI ``fmi`` (2 or 3), reading the outputs with value
    references ``outputs`` after steps of ``step`` (a C expression, s)."""
    text = {2: _FMI2, 3: _FMI3}[fmi]
    return text % {"out0": outputs[0], "out1": outputs[1], "step": step}
