/* A minimal FMI 3.0 co-simulation host, the FMI 3 twin of fmi2_host.c (same arguments).
 *
 * usage: fmi3_host UNZIPPED_DIR MODEL_IDENTIFIER TOKEN STOP|none STEP N_STEPS VR[,VR...]
 *                  [rVR=VALUE ...]
 *
 * dlopens UNZIPPED_DIR/binaries/x86_64-linux/MODEL_IDENTIFIER.so with RTLD_NOW | RTLD_LOCAL,
 * instantiates for co-simulation (logging on), enters initialization mode (start 0, stop STOP
 * or none), sets the given Float64 values (rVR=VALUE), exits initialization mode, does N_STEPS
 * steps of STEP seconds and prints "t v1 v2 ..." (%.17g) after initialization and after every
 * step; then terminates, frees the instance, reports the shared libraries mapped into the
 * process ("fmi3_host: mapped PATH" lines on stderr, from /proc/self/maps) and dlcloses the
 * library. Exit code 0 only if every FMI call returned fmi3OK.
 */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi3Instance;
typedef void *fmi3InstanceEnvironment;
typedef unsigned int fmi3ValueReference;
typedef double fmi3Float64;
typedef _Bool fmi3Boolean; /* C99 bool, as fmi3PlatformTypes.h */
typedef int fmi3Status;    /* 0 OK, 1 warning, 2 discard, 3 error, 4 fatal */
typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, const char *,
                                       const char *);

typedef fmi3Instance (*InstantiateT)(const char *, const char *, const char *, fmi3Boolean,
                                     fmi3Boolean, fmi3Boolean, fmi3Boolean,
                                     const fmi3ValueReference *, size_t,
                                     fmi3InstanceEnvironment, fmi3LogMessageCallback, void *);
typedef fmi3Status (*EnterT)(fmi3Instance, fmi3Boolean, fmi3Float64, fmi3Float64, fmi3Boolean,
                             fmi3Float64);
typedef fmi3Status (*CompT)(fmi3Instance);
typedef void (*FreeT)(fmi3Instance);
typedef fmi3Status (*GetT)(fmi3Instance, const fmi3ValueReference *, size_t, fmi3Float64 *,
                           size_t);
typedef fmi3Status (*SetT)(fmi3Instance, const fmi3ValueReference *, size_t,
                           const fmi3Float64 *, size_t);
typedef fmi3Status (*DoStepT)(fmi3Instance, fmi3Float64, fmi3Float64, fmi3Boolean,
                              fmi3Boolean *, fmi3Boolean *, fmi3Boolean *, fmi3Float64 *);

static void logger(fmi3InstanceEnvironment env, fmi3Status status, const char *category,
                   const char *message) {
    (void)env;
    fprintf(stderr, "status %d %s: %s\n", status, category ? category : "",
            message ? message : "");
}

static void *sym(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p) {
        fprintf(stderr, "fmi3_host: missing symbol %s: %s\n", name, dlerror());
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
        fmi3Status s_ = (call);                                            \
        if (s_ != 0) {                                                     \
            fprintf(stderr, "fmi3_host: %s returned status %d\n", what, s_); \
            return 3;                                                      \
        }                                                                  \
    } while (0)

int main(int argc, char **argv) {
    if (argc < 8) {
        fprintf(stderr, "usage: fmi3_host DIR ID TOKEN STOP|none STEP N VR[,VR...] [rVR=X ...]\n");
        return 2;
    }
    const char *dir = argv[1], *id = argv[2], *token = argv[3];
    int has_stop = strcmp(argv[4], "none") != 0;
    double stop = has_stop ? strtod(argv[4], NULL) : 0.0;
    double h = strtod(argv[5], NULL);
    long n = strtol(argv[6], NULL, 10);
    fmi3ValueReference vrs[256];
    size_t nvr = 0;
    char *list = strdup(argv[7]);
    for (char *tok = strtok(list, ","); tok && nvr < 256; tok = strtok(NULL, ","))
        vrs[nvr++] = (fmi3ValueReference)strtoul(tok, NULL, 10);
    free(list);

    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/x86_64-linux/%s.so", dir, id);
    snprintf(resources, sizeof resources, "%s/resources/", dir);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "fmi3_host: dlopen failed: %s\n", dlerror());
        return 4;
    }
    InstantiateT instantiate = (InstantiateT)sym(lib, "fmi3InstantiateCoSimulation");
    EnterT enter = (EnterT)sym(lib, "fmi3EnterInitializationMode");
    CompT exit_init = (CompT)sym(lib, "fmi3ExitInitializationMode");
    CompT terminate = (CompT)sym(lib, "fmi3Terminate");
    FreeT free_instance = (FreeT)sym(lib, "fmi3FreeInstance");
    GetT get = (GetT)sym(lib, "fmi3GetFloat64");
    SetT set = (SetT)sym(lib, "fmi3SetFloat64");
    DoStepT do_step = (DoStepT)sym(lib, "fmi3DoStep");

    fmi3Instance c = instantiate("host", token, resources, 0, 1, 0, 0, NULL, 0, NULL, logger,
                                 NULL);
    if (!c) {
        fprintf(stderr, "fmi3_host: fmi3InstantiateCoSimulation failed\n");
        return 3;
    }
    CHECK(enter(c, 0, 0.0, 0.0, has_stop, stop), "fmi3EnterInitializationMode");
    for (int a = 8; a < argc; a++) {
        unsigned vr;
        double x;
        if (sscanf(argv[a], "r%u=%lf", &vr, &x) != 2) {
            fprintf(stderr, "fmi3_host: bad setting %s\n", argv[a]);
            return 2;
        }
        fmi3ValueReference r = vr;
        CHECK(set(c, &r, 1, &x, 1), "fmi3SetFloat64");
    }
    CHECK(exit_init(c), "fmi3ExitInitializationMode");
    double values[256];
    for (long k = 0; k <= n; k++) {
        if (k > 0) {
            fmi3Boolean event = 0, term = 0, early = 0;
            fmi3Float64 last = 0.0;
            CHECK(do_step(c, (k - 1) * h, h, 1, &event, &term, &early, &last), "fmi3DoStep");
        }
        CHECK(get(c, vrs, nvr, values, nvr), "fmi3GetFloat64");
        printf("%.17g", k * h);
        for (size_t i = 0; i < nvr; i++) printf(" %.17g", values[i]);
        putchar('\n');
    }
    fflush(stdout);
    CHECK(terminate(c), "fmi3Terminate");
    free_instance(c);
    report_mapped("fmi3_host");
    dlclose(lib);
    return 0;
}
