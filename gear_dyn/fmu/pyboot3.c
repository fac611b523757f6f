/* gear_dyn FMU boot library for FMI 3 binaries (pythonfmu3): pyboot.c's boot constructor plus
 * the FMI 3 status wrappers.
 *
 * Built by gear_dyn.fmu.native for ``gear-dyn fmu build --fmi 3``. The constructor (libpython
 * made global, interpreter started as the build interpreter, never finalized) is pyboot.c's,
 * included with its FMI 2 wrappers left out. As for FMI 2, pythonfmu3 answers every refused
 * call with fmi3Fatal although the gear_dyn slave keeps the instance valid when it refuses
 * (a bad parameter value, a pair that cannot mesh): the build renames the binary's
 * fmi3Set{Float64,Int32,Int64,Boolean,String} and fmi3ExitInitializationMode to
 * gear_dyn_orig_* (patchelf --rename-dynamic-symbols); the functions below take their names,
 * call the originals and report such a refusal as fmi3Error. fmi3InstantiateCoSimulation is
 * wrapped to drop pythonfmu3's second, technical message ("Fatal py exception encountered:
 * ...") so the host sees the slave's one message.
 */
#define GEAR_DYN_BOOT_ONLY
#include "pyboot.c"

#include <stdbool.h>
#include <stddef.h>

typedef int Status3; /* fmi3OK 0, fmi3Warning 1, fmi3Discard 2, fmi3Error 3, fmi3Fatal 4 */
typedef void (*Logger3)(void *, Status3, const char *, const char *);

static void *original3(const char *name) {
    static void *self = NULL;
    if (!self) {
        Dl_info info;
        char path[4096];
        if (!dladdr((void *)&original3, &info) || !info.dli_fname) return NULL;
        snprintf(path, sizeof path, "%s", info.dli_fname);
        char *slash = strrchr(path, '/');
        snprintf(slash ? slash + 1 : path, sizeof path - (size_t)(slash ? slash + 1 - path : 0),
                 "%s.so", GEAR_DYN_MODEL);
        self = dlopen(path, RTLD_NOW | RTLD_NOLOAD);
        if (!self) return NULL;
    }
    char full[128];
    snprintf(full, sizeof full, "gear_dyn_orig_%s", name);
    return dlsym(self, full);
}

/* one slot per instantiation (recycled after MAX_LOGGERS3 instantiations): the wrapped
 * callback gets the slot as its environment, the slot holds the host's logger and environment */
#define MAX_LOGGERS3 1024
typedef struct { void *env; Logger3 logger; } Slot3;
static Slot3 loggers3[MAX_LOGGERS3];

static void filtered_logger3(void *env, Status3 status, const char *category,
                             const char *message) {
    if (message && strncmp(message, "Fatal py exception encountered", 30) == 0) return;
    Slot3 *slot = (Slot3 *)env;
    if (slot && slot->logger) slot->logger(slot->env, status, category, message);
}

void *fmi3InstantiateCoSimulation(const char *name, const char *token, const char *resources,
                                  bool visible, bool logging, bool event_mode, bool early_return,
                                  const unsigned *required, size_t n_required, void *env,
                                  Logger3 logger, void *intermediate) {
    typedef void *(*Fn)(const char *, const char *, const char *, bool, bool, bool, bool,
                        const unsigned *, size_t, void *, Logger3, void *);
    Fn fn = (Fn)original3("fmi3InstantiateCoSimulation");
    if (!fn) return NULL;
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

static Status3 recoverable3(Status3 s) { return s == 4 ? 3 : s; }

#define WRAP_SET3(NAME, T)                                                                 \
    Status3 NAME(void *c, const unsigned *vr, size_t n, const T *values, size_t n_values) {  \
        typedef Status3 (*Fn)(void *, const unsigned *, size_t, const T *, size_t);          \
        Fn fn = (Fn)original3(#NAME);                                                        \
        return fn ? recoverable3(fn(c, vr, n, values, n_values)) : 4;                        \
    }
WRAP_SET3(fmi3SetFloat64, double)
WRAP_SET3(fmi3SetInt32, int)
WRAP_SET3(fmi3SetInt64, long long)
WRAP_SET3(fmi3SetBoolean, bool)
WRAP_SET3(fmi3SetString, char *)

Status3 fmi3ExitInitializationMode(void *c) {
    typedef Status3 (*Fn)(void *);
    Fn fn = (Fn)original3("fmi3ExitInitializationMode");
    return fn ? recoverable3(fn(c)) : 4;
}
