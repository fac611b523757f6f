/* gear_dyn FMU boot library: lets any FMI host run the pythonfmu binary next to it.
 *
 * Built by gear_dyn.fmu.native at FMU build time and added as a needed library of
 * binaries/linux64/<id>.so (patchelf), so it is loaded - and its constructor runs - before the
 * pythonfmu binary is used. When the host process has no Python interpreter yet (a C host),
 * the constructor:
 *   1. makes libpython global in the process (hosts dlopen the FMU with RTLD_LOCAL, and the
 *      extension modules of numpy and scipy resolve the Python C API in the global scope);
 *   2. starts the interpreter as the build interpreter GEAR_DYN_PYTHON would (so its prefix,
 *      virtual environment and site-packages are found with no environment variable), without
 *      signal handlers, and releases the GIL;
 * and it never finalizes the interpreter: pythonfmu then leaves it alone too (it finalizes only
 * an interpreter it started itself), which is what crashed C hosts at exit (numpy and scipy do
 * not survive Py_Finalize in an embedded interpreter). In a Python host (fmpy) it does nothing.
 *
 * Status semantics: pythonfmu answers every failed call with fmi2Fatal, although the gear_dyn
 * slave keeps the instance valid when it refuses a call (a bad parameter value, a pair that
 * cannot mesh, a doStep out of order, an FMU state of another FMU). The build renames the
 * binary's functions listed in gear_dyn.fmu.native.WRAPPED to gear_dyn_orig_* (patchelf
 * --rename-dynamic-symbols); the functions below take their names and call the originals;
 * when the slave logged its refusal (status fmi2Error) during the call, pythonfmu's
 * fmi2Fatal becomes fmi2Error; any other failure stays fmi2Fatal. fmi2Instantiate is wrapped
 * too, to drop pythonfmu's second, technical message ("Fatal py exception encountered: ...")
 * so the host sees the slave's one message, and to register the exit handler below.
 */
#include <Python.h>
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GEAR_DYN_LIBPYTHON
#error "GEAR_DYN_LIBPYTHON (soname of libpython) must be defined"
#endif
#ifndef GEAR_DYN_MODEL
#error "GEAR_DYN_MODEL (model identifier) must be defined"
#endif
#ifndef GEAR_DYN_PYTHON
#error "GEAR_DYN_PYTHON (path of the build interpreter) must be defined"
#endif

__attribute__((constructor)) static void gear_dyn_boot(void) {
    if (Py_IsInitialized()) return; /* a Python host: its interpreter runs the FMU */
    if (!dlopen(GEAR_DYN_LIBPYTHON, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD)) {
        fprintf(stderr, "gear_dyn FMU: cannot make %s global: %s\n", GEAR_DYN_LIBPYTHON,
                dlerror());
        return;
    }
    PyConfig config;
    PyConfig_InitPythonConfig(&config);
    config.install_signal_handlers = 0;
    config.parse_argv = 0;
    PyStatus status = PyConfig_SetBytesString(&config, &config.program_name, GEAR_DYN_PYTHON);
    if (!PyStatus_Exception(status)) status = Py_InitializeFromConfig(&config);
    PyConfig_Clear(&config);
    if (PyStatus_Exception(status)) {
        fprintf(stderr, "gear_dyn FMU: cannot start Python (%s): %s\n", GEAR_DYN_PYTHON,
                status.err_msg ? status.err_msg : "unknown error");
        return;
    }
    PyRun_SimpleString("import sys; sys.gear_dyn_embedded = True");
    PyEval_SaveThread(); /* pythonfmu takes the GIL per call (PyGILState_Ensure) */
}

/* ------------------------------------------------------------------ shared by FMI 2 and 3
 * (pyboot3.c includes this file with GEAR_DYN_BOOT_ONLY: the parts below, not the FMI 2
 * wrappers) */
/* the FMU binary next to this library (a reference kept: it is never unloaded before us) */
static void *binary(void) {
    static void *self = NULL;
    if (!self) {
        Dl_info info;
        char path[4096];
        if (!dladdr((void *)&binary, &info) || !info.dli_fname) return NULL;
        snprintf(path, sizeof path, "%s", info.dli_fname);
        char *slash = strrchr(path, '/');
        snprintf(slash ? slash + 1 : path, sizeof path - (size_t)(slash ? slash + 1 - path : 0),
                 "%s.so", GEAR_DYN_MODEL);
        self = dlopen(path, RTLD_NOW | RTLD_NOLOAD);
    }
    return self;
}

static void *original(const char *name) {
    void *self = binary();
    if (!self) return NULL;
    char full[128];
    snprintf(full, sizeof full, "gear_dyn_orig_%s", name);
    return dlsym(self, full);
}

/* ------------------------------------------------------------------ clean exit
 * pythonfmu 0.7 keeps its interpreter state in a static std::shared_ptr (pyState). At exit, the
 * C++ exit handler of the binary destroys that shared_ptr (freeing the PyState block), and then
 * the binary's ELF destructor calls finalizePythonInterpreter(), which assigns nullptr to the
 * destroyed shared_ptr: it decrements the reference count inside the freed block (valgrind:
 * "Invalid read of size 4 ... inside a block of size 128 free'd"). When glibc has put that block
 * on a bin list, the write lands on the list's pointers, and a later free at exit (libgfortran's
 * exit handler, from scipy) aborts with "corrupted double-linked list" - in about 1 of 30 fmpy
 * processes. pythonfmu3 (FMI 3) has the same code and the same fault. The handler below is
 * registered at the first fmi2Instantiate (fmi3InstantiateCoSimulation), after the binary's
 * own, so it runs before them (exit handlers run in reverse order): it calls
 * finalizePythonInterpreter() while the shared_ptr is alive; the two later calls then find it
 * empty. It never finalizes Python (pythonfmu does that only for an interpreter it started,
 * and in both kinds of host the interpreter was running before the FMU: see gear_dyn_boot). */
static void release_pystate(void) {
    void *self = binary();
    void (*fin)(void) = self ? (void (*)(void))dlsym(self, "finalizePythonInterpreter") : NULL;
    if (fin) fin();
}

/* called by the instantiate wrappers, after the binary has registered its own exit handlers */
static void register_exit_handler(void) {
    static int done = 0;
    if (!done) done = atexit(release_pystate) == 0;
}

/* Set when the slave logs a status-error message during a call: the slave logs one only when
 * it refuses a call and keeps the instance valid (GearDynSlave._refuse). Per thread: the FMI
 * call, its Python code and the logger run in one thread. A failure without such a message
 * (the instance may be lost) stays fmi2Fatal (fmi3Fatal). */
static __thread int refused = 0;

/* the status of a call: Fatal (4) becomes Error (3) when the slave refused it (FMI 2 and FMI 3
 * number these two alike); the flag is cleared for the next call */
static int recoverable(int s) {
    int r = refused;
    refused = 0;
    return (s == 4 && r) ? 3 : s;
}

/* a wrapper NAME of the binary's renamed original (looked up once), called with the refusal
 * flag clear; FMI 2 and FMI 3 statuses are ints (enums) */
#define WRAP(NAME, PARAMS, ARGS)                                                        \
    int NAME PARAMS {                                                                   \
        typedef int(*Fn) PARAMS;                                                        \
        static Fn fn = NULL;                                                            \
        if (!fn) fn = (Fn)original(#NAME);                                              \
        if (!fn) return 4;                                                              \
        refused = 0;                                                                    \
        return recoverable(fn ARGS);                                                    \
    }

/* ------------------------------------------------------------------ FMI 2 wrappers */
#ifndef GEAR_DYN_BOOT_ONLY /* defined by pyboot3.c (FMI 3) */
typedef int Status; /* fmi2OK 0, fmi2Warning 1, fmi2Discard 2, fmi2Error 3, fmi2Fatal 4 */
typedef void (*Logger)(void *, const char *, Status, const char *, const char *, ...);
typedef struct {
    Logger logger;
    void *allocate, *free_memory, *step_finished, *environment;
} Callbacks;

/* one slot per instantiation (recycled after MAX_LOGGERS instantiations): the wrapped
 * callbacks carry the slot as their environment, the slot the host's logger and environment */
#define MAX_LOGGERS 1024
typedef struct { void *env; Logger logger; } Slot;
static Slot loggers[MAX_LOGGERS];

static void filtered_logger(void *env, const char *instance, Status status, const char *category,
                            const char *message, ...) {
    char text[8192];
    va_list ap;
    va_start(ap, message);
    vsnprintf(text, sizeof text, message, ap);
    va_end(ap);
    if (strncmp(text, "Fatal py exception encountered", 30) == 0) return;
    if (status == 3) refused = 1; /* the slave's refusal (see recoverable) */
    /* the message is passed as the format (hosts such as fmpy do not format it): % doubled */
    char escaped[16384];
    size_t k = 0;
    for (const char *p = text; *p && k + 2 < sizeof escaped; p++) {
        escaped[k++] = *p;
        if (*p == '%') escaped[k++] = '%';
    }
    escaped[k] = '\0';
    Slot *slot = (Slot *)env;
    if (slot && slot->logger) slot->logger(slot->env, instance, status, category, escaped);
}

void *fmi2Instantiate(const char *name, int type, const char *guid, const char *resources,
                      const Callbacks *cb, int visible, int logging) {
    typedef void *(*Fn)(const char *, int, const char *, const char *, const Callbacks *, int,
                        int);
    Fn fn = (Fn)original("fmi2Instantiate");
    if (!fn) return NULL;
    register_exit_handler();
    if (!cb || !cb->logger) return fn(name, type, guid, resources, cb, visible, logging);
    static Callbacks copies[MAX_LOGGERS];
    static int next = 0;
    int slot = next++ % MAX_LOGGERS;
    loggers[slot].env = cb->environment;
    loggers[slot].logger = cb->logger;
    copies[slot] = *cb;
    copies[slot].logger = filtered_logger;
    copies[slot].environment = &loggers[slot];
    return fn(name, type, guid, resources, &copies[slot], visible, logging);
}

typedef unsigned VR;
WRAP(fmi2SetReal, (void *c, const VR *vr, size_t n, const double *x), (c, vr, n, x))
WRAP(fmi2SetInteger, (void *c, const VR *vr, size_t n, const int *x), (c, vr, n, x))
WRAP(fmi2SetBoolean, (void *c, const VR *vr, size_t n, const int *x), (c, vr, n, x))
WRAP(fmi2SetString, (void *c, const VR *vr, size_t n, char *const *x), (c, vr, n, x))
WRAP(fmi2GetReal, (void *c, const VR *vr, size_t n, double *x), (c, vr, n, x))
WRAP(fmi2SetupExperiment, (void *c, int tol_on, double tol, double t0, int stop_on, double t1),
     (c, tol_on, tol, t0, stop_on, t1))
WRAP(fmi2EnterInitializationMode, (void *c), (c))
WRAP(fmi2ExitInitializationMode, (void *c), (c))
WRAP(fmi2DoStep, (void *c, double t, double h, int no_prior), (c, t, h, no_prior))
WRAP(fmi2Terminate, (void *c), (c))
WRAP(fmi2GetFMUstate, (void *c, void **state), (c, state))
WRAP(fmi2SetFMUstate, (void *c, void *state), (c, state))
WRAP(fmi2SerializedFMUstateSize, (void *c, void *state, size_t *size), (c, state, size))
WRAP(fmi2SerializeFMUstate, (void *c, void *state, char *bytes, size_t size),
     (c, state, bytes, size))
WRAP(fmi2DeSerializeFMUstate, (void *c, const char *bytes, size_t size, void **state),
     (c, bytes, size, state))
#endif /* GEAR_DYN_BOOT_ONLY */
