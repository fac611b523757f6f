/* gear_dyn FMU boot library for FMI 3 binaries (pythonfmu3): pyboot.c's boot constructor and
 * clean exit plus the FMI 3 status wrappers.
 *
 * Built by gear_dyn.fmu.native for ``gear-dyn fmu build --fmi 3``. pyboot.c is included with
 * its FMI 2 wrappers left out: the constructor (libpython made global, interpreter started as
 * the build interpreter, never finalized), the lookup of the binary's renamed functions, the
 * exit handler (pythonfmu3 has pythonfmu 0.7's use-after-free of its static interpreter state
 * at exit: see release_pystate in pyboot.c) and the refusal flag. As for FMI 2, pythonfmu3
 * answers every refused call with fmi3Fatal although the gear_dyn slave keeps the instance
 * valid when it refuses (a bad parameter value, a pair that cannot mesh, a doStep out of order,
 * an FMU state of another FMU): the build renames the binary's functions listed in
 * gear_dyn.fmu.native.WRAPPED3 to gear_dyn_orig_* (patchelf --rename-dynamic-symbols); the
 * functions below take their names and call the originals; when the slave logged its refusal
 * (status fmi3Error) during the call, fmi3Fatal becomes fmi3Error; any other failure stays
 * fmi3Fatal. fmi3InstantiateCoSimulation is wrapped to drop pythonfmu3's second, technical
 * message ("Fatal py exception encountered: ...") so the host sees the slave's one message,
 * and to register the exit handler.
 */
#define GEAR_DYN_BOOT_ONLY
#include "pyboot.c"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef int Status3; /* fmi3OK 0, fmi3Warning 1, fmi3Discard 2, fmi3Error 3, fmi3Fatal 4 */
typedef void (*Logger3)(void *, Status3, const char *, const char *);

/* one slot per instantiation (recycled after MAX_LOGGERS3 instantiations): the wrapped
 * callback gets the slot as its environment, the slot holds the host's logger and environment */
#define MAX_LOGGERS3 1024
typedef struct { void *env; Logger3 logger; } Slot3;
static Slot3 loggers3[MAX_LOGGERS3];

static void filtered_logger3(void *env, Status3 status, const char *category,
                             const char *message) {
    if (message && strncmp(message, "Fatal py exception encountered", 30) == 0) return;
    if (status == 3) refused = 1; /* the slave's refusal (see recoverable in pyboot.c) */
    Slot3 *slot = (Slot3 *)env;
    if (slot && slot->logger) slot->logger(slot->env, status, category, message);
}

void *fmi3InstantiateCoSimulation(const char *name, const char *token, const char *resources,
                                  bool visible, bool logging, bool event_mode, bool early_return,
                                  const unsigned *required, size_t n_required, void *env,
                                  Logger3 logger, void *intermediate) {
    typedef void *(*Fn)(const char *, const char *, const char *, bool, bool, bool, bool,
                        const unsigned *, size_t, void *, Logger3, void *);
    Fn fn = (Fn)original("fmi3InstantiateCoSimulation");
    if (!fn) return NULL;
    register_exit_handler();
    if (!logger)
        return fn(name, token, resources, visible, logging, event_mode, early_return, required,
                  n_required, env, logger, intermediate);
    static int next = 0;
    int slot = next++ % MAX_LOGGERS3;
    loggers3[slot].env = env;
    loggers3[slot].logger = logger;
    return fn(name, token, resources, visible, logging, event_mode, early_return, required,
              n_required, &loggers3[slot], filtered_logger3, intermediate);
}

typedef unsigned VR3;
#define SET3(NAME, T) \
    WRAP(NAME, (void *c, const VR3 *vr, size_t n, const T *x, size_t nx), (c, vr, n, x, nx))
SET3(fmi3SetFloat64, double)
SET3(fmi3SetInt32, int32_t)
SET3(fmi3SetInt64, int64_t)
SET3(fmi3SetBoolean, bool)
SET3(fmi3SetString, char *)
WRAP(fmi3GetFloat64, (void *c, const VR3 *vr, size_t n, double *x, size_t nx),
      (c, vr, n, x, nx))
WRAP(fmi3EnterInitializationMode,
      (void *c, bool tol_on, double tol, double t0, bool stop_on, double t1),
      (c, tol_on, tol, t0, stop_on, t1))
WRAP(fmi3ExitInitializationMode, (void *c), (c))
WRAP(fmi3DoStep,
      (void *c, double t, double h, bool no_prior, bool *event, bool *terminate, bool *early,
       double *last),
      (c, t, h, no_prior, event, terminate, early, last))
WRAP(fmi3Terminate, (void *c), (c))
WRAP(fmi3GetFMUState, (void *c, void **state), (c, state))
WRAP(fmi3SetFMUState, (void *c, void *state), (c, state))
WRAP(fmi3SerializedFMUStateSize, (void *c, void *state, size_t *size), (c, state, size))
WRAP(fmi3SerializeFMUState, (void *c, void *state, uint8_t *bytes, size_t size),
      (c, state, bytes, size))
WRAP(fmi3DeserializeFMUState, (void *c, const uint8_t *bytes, size_t size, void **state),
      (c, bytes, size, state))
