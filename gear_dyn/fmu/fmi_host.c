/* A minimal FMI 2.0 or 3.0 co-simulation host, as C masters (fmuCheck, OMSimulator, ...) load an
 * FMU. Compiled as fmi2_host by default, as fmi3_host with -DFMI_VERSION=3 (same arguments).
 *
 * usage: fmiN_host UNZIPPED_DIR MODEL_IDENTIFIER GUID|TOKEN STOP|none STEP N_STEPS VR[,VR...]
 *                  [rVR=VALUE ...]
 *
 * dlopens UNZIPPED_DIR/binaries/PLATFORM/MODEL_IDENTIFIER.so (linux64 for FMI 2, x86_64-linux
 * for FMI 3) with RTLD_NOW | RTLD_LOCAL, instantiates for co-simulation (logging on), starts
 * initialization (start 0, stop STOP or none: fmi2SetupExperiment, or fmi3EnterInitialization-
 * Mode's arguments), sets the given Real/Float64 values (rVR=VALUE) in initialization mode,
 * exits it, does N_STEPS steps of STEP seconds and prints "t v1 v2 ..." (%.17g) after
 * initialization and after every step; then terminates, frees the instance, reports the shared
 * libraries mapped into the process ("fmiN_host: mapped PATH" lines on stderr, from
 * /proc/self/maps) and dlcloses the library. Exit code 0 only if every FMI call returned OK.
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef FMI_VERSION
#define FMI_VERSION 2
#endif

typedef void *Instance;
typedef void *Environment;
typedef unsigned int ValueReference;
typedef int Status; /* 0 OK, 1 warning, 2 discard, 3 error, 4 fatal (FMI 2: 5 pending) */
typedef Status (*CompT)(Instance);
typedef void (*FreeT)(Instance);

#if FMI_VERSION == 3
#define HOST "fmi3_host"
#define PLATFORM "x86_64-linux"
#define FMI(name) "fmi3" name
#define SET_NAME "fmi3SetFloat64"
#define GET_NAME "fmi3GetFloat64"
typedef _Bool Boolean; /* C99 bool, as fmi3PlatformTypes.h */
typedef void (*LogT)(Environment, Status, const char *, const char *);
typedef Instance (*InstantiateT)(const char *, const char *, const char *, Boolean, Boolean,
                                 Boolean, Boolean, const ValueReference *, size_t, Environment,
                                 LogT, void *);
typedef Status (*EnterT)(Instance, Boolean, double, double, Boolean, double);
typedef Status (*GetT)(Instance, const ValueReference *, size_t, double *, size_t);
typedef Status (*SetT)(Instance, const ValueReference *, size_t, const double *, size_t);
typedef Status (*DoStepT)(Instance, double, double, Boolean, Boolean *, Boolean *, Boolean *,
                          double *);

static void logger(Environment env, Status status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "status %d %s: %s\n", status, category ? category : "",
            message ? message : "");
}
#else
#define HOST "fmi2_host"
#define PLATFORM "linux64"
#define FMI(name) "fmi2" name
#define SET_NAME "fmi2SetReal"
#define GET_NAME "fmi2GetReal"
typedef int Boolean;
typedef void (*LogT)(Environment, const char *, Status, const char *, const char *, ...);
typedef struct {
    LogT logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(Environment, Status);
    Environment componentEnvironment;
} Callbacks;
typedef Instance (*InstantiateT)(const char *, int, const char *, const char *,
                                 const Callbacks *, Boolean, Boolean);
typedef Status (*SetupT)(Instance, Boolean, double, double, Boolean, double);
typedef Status (*GetT)(Instance, const ValueReference *, size_t, double *);
typedef Status (*SetT)(Instance, const ValueReference *, size_t, const double *);
typedef Status (*DoStepT)(Instance, double, double, Boolean);

static void logger(Environment env, const char *name, Status status, const char *category,
                   const char *message, ...) {
    va_list ap;
    (void)env;
    fprintf(stderr, "[%s] status %d %s: ", name ? name : "?", status, category ? category : "");
    va_start(ap, message);
    vfprintf(stderr, message, ap);
    va_end(ap);
    fputc('\n', stderr);
}
#endif

static void *sym(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p) {
        fprintf(stderr, HOST ": missing symbol %s: %s\n", name, dlerror());
        exit(4);
    }
    return p;
}

/* every shared library mapped into this process, one "HOST: mapped PATH" line each on stderr
 * (from /proc/self/maps, Linux): the caller checks that no libpython was loaded */
static void report_mapped(void) {
    FILE *maps = fopen("/proc/self/maps", "r");
    char line[4352], last[4096] = "";
    if (!maps) return;
    while (fgets(line, sizeof line, maps)) {
        char *path = strchr(line, '/');
        if (!path || !strstr(path, ".so")) continue;
        path[strcspn(path, "\n")] = '\0';
        if (strcmp(path, last) == 0) continue;
        strncpy(last, path, sizeof last - 1);
        fprintf(stderr, HOST ": mapped %s\n", path);
    }
    fclose(maps);
}

#define CHECK(call, what)                                                  \
    do {                                                                   \
        Status s_ = (call);                                                \
        if (s_ != 0) {                                                     \
            fprintf(stderr, HOST ": %s returned status %d\n", what, s_);   \
            return 3;                                                      \
        }                                                                  \
    } while (0)

int main(int argc, char **argv) {
    if (argc < 8) {
        fprintf(stderr, "usage: " HOST " DIR ID GUID|TOKEN STOP|none STEP N VR[,VR...] "
                "[rVR=X ...]\n");
        return 2;
    }
    const char *dir = argv[1], *id = argv[2], *token = argv[3];
    int has_stop = strcmp(argv[4], "none") != 0;
    double stop = has_stop ? strtod(argv[4], NULL) : 0.0;
    double h = strtod(argv[5], NULL);
    long n = strtol(argv[6], NULL, 10);
    ValueReference vrs[256];
    size_t nvr = 0;
    char *list = strdup(argv[7]);
    for (char *tok = strtok(list, ","); tok && nvr < 256; tok = strtok(NULL, ","))
        vrs[nvr++] = (ValueReference)strtoul(tok, NULL, 10);
    free(list);

    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/" PLATFORM "/%s.so", dir, id);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, HOST ": dlopen failed: %s\n", dlerror());
        return 4;
    }
    CompT exit_init = (CompT)sym(lib, FMI("ExitInitializationMode"));
    CompT terminate = (CompT)sym(lib, FMI("Terminate"));
    FreeT free_instance = (FreeT)sym(lib, FMI("FreeInstance"));
    DoStepT do_step = (DoStepT)sym(lib, FMI("DoStep"));
    GetT get = (GetT)sym(lib, GET_NAME);
    SetT set = (SetT)sym(lib, SET_NAME);
#if FMI_VERSION == 3
    InstantiateT instantiate = (InstantiateT)sym(lib, "fmi3InstantiateCoSimulation");
    EnterT enter = (EnterT)sym(lib, "fmi3EnterInitializationMode");
    snprintf(resources, sizeof resources, "%s/resources/", dir);
    Instance c = instantiate("host", token, resources, 0, 1, 0, 0, NULL, 0, NULL, logger, NULL);
#define SET(r, x) set(c, &r, 1, &x, 1)
#define GET(values) get(c, vrs, nvr, values, nvr)
#else
    InstantiateT instantiate = (InstantiateT)sym(lib, "fmi2Instantiate");
    SetupT setup = (SetupT)sym(lib, "fmi2SetupExperiment");
    CompT enter = (CompT)sym(lib, "fmi2EnterInitializationMode");
    snprintf(resources, sizeof resources, "file://%s/resources", dir);
    Callbacks cb = {logger, calloc, free, NULL, NULL};
    Instance c = instantiate("host", 1 /* fmi2CoSimulation */, token, resources, &cb, 0, 1);
#define SET(r, x) set(c, &r, 1, &x)
#define GET(values) get(c, vrs, nvr, values)
#endif
    if (!c) {
        fprintf(stderr, HOST ": instantiation failed\n");
        return 3;
    }
#if FMI_VERSION == 3
    CHECK(enter(c, 0, 0.0, 0.0, has_stop, stop), "fmi3EnterInitializationMode");
#else
    CHECK(setup(c, 0, 0.0, 0.0, has_stop, stop), "fmi2SetupExperiment");
    CHECK(enter(c), "fmi2EnterInitializationMode");
#endif
    for (int a = 8; a < argc; a++) {
        unsigned vr;
        double x;
        if (sscanf(argv[a], "r%u=%lf", &vr, &x) != 2) {
            fprintf(stderr, HOST ": bad setting %s\n", argv[a]);
            return 2;
        }
        ValueReference r = vr;
        CHECK(SET(r, x), SET_NAME);
    }
    CHECK(exit_init(c), FMI("ExitInitializationMode"));
    double values[256];
    for (long k = 0; k <= n; k++) {
        if (k > 0) {
#if FMI_VERSION == 3
            Boolean event = 0, term = 0, early = 0;
            double last = 0.0;
            CHECK(do_step(c, (k - 1) * h, h, 1, &event, &term, &early, &last), "fmi3DoStep");
#else
            CHECK(do_step(c, (k - 1) * h, h, 1), "fmi2DoStep");
#endif
        }
        CHECK(GET(values), GET_NAME);
        printf("%.17g", k * h);
        for (size_t i = 0; i < nvr; i++) printf(" %.17g", values[i]);
        putchar('\n');
    }
    fflush(stdout);
    CHECK(terminate(c), FMI("Terminate"));
    free_instance(c);
    report_mapped();
    dlclose(lib);
    return 0;
}
