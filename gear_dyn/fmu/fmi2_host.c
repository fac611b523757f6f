/* A minimal FMI 2.0 co-simulation host, as C masters (fmuCheck, OMSimulator, ...) load an FMU.
 *
 * usage: fmi2_host UNZIPPED_DIR MODEL_IDENTIFIER GUID STOP|none STEP N_STEPS VR[,VR...]
 *                  [rVR=VALUE ...]
 *
 * dlopens UNZIPPED_DIR/binaries/linux64/MODEL_IDENTIFIER.so with RTLD_NOW | RTLD_LOCAL,
 * instantiates (logging on), sets the given Real values (rVR=VALUE), sets up the experiment
 * (start 0, stop STOP or none), initializes, does N_STEPS steps of STEP seconds and prints
 * "t v1 v2 ..." (%.17g) after initialization and after every step; then terminates, frees the
 * instance, reports the shared libraries mapped into the process ("fmi2_host: mapped PATH"
 * lines on stderr, from /proc/self/maps) and dlcloses the library. Exit code 0 only if every
 * FMI call returned fmi2OK.
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Boolean;
typedef int fmi2Status; /* 0 OK, 1 warning, 2 discard, 3 error, 4 fatal, 5 pending */
typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, const char *, fmi2Status,
                                   const char *, const char *, ...);
typedef struct {
    fmi2CallbackLogger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(fmi2ComponentEnvironment, fmi2Status);
    fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

typedef fmi2Component (*InstantiateT)(const char *, int, const char *, const char *,
                                      const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*SetupT)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
                             fmi2Real);
typedef fmi2Status (*CompT)(fmi2Component);
typedef void (*FreeT)(fmi2Component);
typedef fmi2Status (*RealT)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef fmi2Status (*SetRealT)(fmi2Component, const fmi2ValueReference *, size_t,
                               const fmi2Real *);
typedef fmi2Status (*DoStepT)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);

static void logger(fmi2ComponentEnvironment env, const char *name, fmi2Status status,
                   const char *category, const char *message, ...) {
    va_list ap;
    (void)env;
    fprintf(stderr, "[%s] status %d %s: ", name ? name : "?", status, category ? category : "");
    va_start(ap, message);
    vfprintf(stderr, message, ap);
    va_end(ap);
    fputc('\n', stderr);
}

static void *sym(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p) {
        fprintf(stderr, "fmi2_host: missing symbol %s: %s\n", name, dlerror());
        exit(4);
    }
    return p;
}

/* every shared library mapped into this process, one "HOST: mapped PATH" line each on stderr
 * (from /proc/self/maps, Linux): the caller checks that no libpython was loaded */
static void report_mapped(const char *host) {
    FILE *maps = fopen("/proc/self/maps", "r");
    char line[4352], last[4096] = "";
    if (!maps) return;
    while (fgets(line, sizeof line, maps)) {
        char *path = strchr(line, '/');
        if (!path || !strstr(path, ".so")) continue;
        path[strcspn(path, "\n")] = '\0';
        if (strcmp(path, last) == 0) continue;
        strncpy(last, path, sizeof last - 1);
        fprintf(stderr, "%s: mapped %s\n", host, path);
    }
    fclose(maps);
}

#define CHECK(call, what)                                                  \
    do {                                                                   \
        fmi2Status s_ = (call);                                            \
        if (s_ != 0) {                                                     \
            fprintf(stderr, "fmi2_host: %s returned status %d\n", what, s_); \
            return 3;                                                      \
        }                                                                  \
    } while (0)

int main(int argc, char **argv) {
    if (argc < 8) {
        fprintf(stderr, "usage: fmi2_host DIR ID GUID STOP|none STEP N VR[,VR...] [rVR=X ...]\n");
        return 2;
    }
    const char *dir = argv[1], *id = argv[2], *guid = argv[3];
    int has_stop = strcmp(argv[4], "none") != 0;
    double stop = has_stop ? strtod(argv[4], NULL) : 0.0;
    double h = strtod(argv[5], NULL);
    long n = strtol(argv[6], NULL, 10);
    fmi2ValueReference vrs[256];
    size_t nvr = 0;
    char *list = strdup(argv[7]);
    for (char *tok = strtok(list, ","); tok && nvr < 256; tok = strtok(NULL, ","))
        vrs[nvr++] = (fmi2ValueReference)strtoul(tok, NULL, 10);
    free(list);

    char path[4096], uri[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", dir, id);
    snprintf(uri, sizeof uri, "file://%s/resources", dir);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "fmi2_host: dlopen failed: %s\n", dlerror());
        return 4;
    }
    InstantiateT instantiate = (InstantiateT)sym(lib, "fmi2Instantiate");
    SetupT setup = (SetupT)sym(lib, "fmi2SetupExperiment");
    CompT enter = (CompT)sym(lib, "fmi2EnterInitializationMode");
    CompT exit_init = (CompT)sym(lib, "fmi2ExitInitializationMode");
    CompT terminate = (CompT)sym(lib, "fmi2Terminate");
    FreeT free_instance = (FreeT)sym(lib, "fmi2FreeInstance");
    RealT get_real = (RealT)sym(lib, "fmi2GetReal");
    SetRealT set_real = (SetRealT)sym(lib, "fmi2SetReal");
    DoStepT do_step = (DoStepT)sym(lib, "fmi2DoStep");

    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = instantiate("host", 1 /* fmi2CoSimulation */, guid, uri, &cb, 0, 1);
    if (!c) {
        fprintf(stderr, "fmi2_host: fmi2Instantiate failed\n");
        return 3;
    }
    CHECK(setup(c, 0, 0.0, 0.0, has_stop, stop), "fmi2SetupExperiment");
    CHECK(enter(c), "fmi2EnterInitializationMode");
    for (int a = 8; a < argc; a++) {
        unsigned vr;
        double x;
        if (sscanf(argv[a], "r%u=%lf", &vr, &x) != 2) {
            fprintf(stderr, "fmi2_host: bad setting %s\n", argv[a]);
            return 2;
        }
        fmi2ValueReference r = vr;
        CHECK(set_real(c, &r, 1, &x), "fmi2SetReal");
    }
    CHECK(exit_init(c), "fmi2ExitInitializationMode");
    double values[256];
    for (long k = 0; k <= n; k++) {
        if (k > 0) CHECK(do_step(c, (k - 1) * h, h, 1), "fmi2DoStep");
        CHECK(get_real(c, vrs, nvr, values), "fmi2GetReal");
        printf("%.17g", k * h);
        for (size_t i = 0; i < nvr; i++) printf(" %.17g", values[i]);
        putchar('\n');
    }
    fflush(stdout);
    CHECK(terminate(c), "fmi2Terminate");
    free_instance(c);
    report_mapped("fmi2_host");
    dlclose(lib);
    return 0;
}
