/* Time one fmi2DoStep of an FMU in a plain C host (benchmarks/bench_native_fmu.py).
 *
 * usage: step_timer UNZIPPED_DIR MODEL_IDENTIFIER GUID STEP N_STEPS REPEATS
 *
 * dlopens binaries/linux64/MODEL_IDENTIFIER.so, instantiates, initializes, then REPEATS times
 * does N_STEPS steps of STEP seconds (clock_gettime(CLOCK_MONOTONIC) around the loop) and prints
 * the time per step of each repeat in nanoseconds, one per line. Exit code 0 only if every FMI
 * call returned fmi2OK.
 */
#define _POSIX_C_SOURCE 199309L
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef void *C;
typedef struct {
    void *logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void *stepFinished;
    void *env;
} Callbacks;
typedef C (*InstantiateT)(const char *, int, const char *, const char *, const Callbacks *, int,
                          int);
typedef int (*SetupT)(C, int, double, double, int, double);
typedef int (*CompT)(C);
typedef int (*DoStepT)(C, double, double, int);

static void *sym(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p) {
        fprintf(stderr, "step_timer: missing %s\n", name);
        exit(4);
    }
    return p;
}

int main(int argc, char **argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: step_timer DIR ID GUID STEP N REPEATS\n");
        return 2;
    }
    char path[4096], uri[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", argv[1], argv[2]);
    snprintf(uri, sizeof uri, "file://%s/resources", argv[1]);
    double h = strtod(argv[4], NULL);
    long n = strtol(argv[5], NULL, 10), repeats = strtol(argv[6], NULL, 10);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "step_timer: %s\n", dlerror());
        return 4;
    }
    Callbacks cb = {NULL, calloc, free, NULL, NULL};
    C c = ((InstantiateT)sym(lib, "fmi2Instantiate"))("t", 1, argv[3], uri, &cb, 0, 0);
    if (!c) return 3;
    if (((SetupT)sym(lib, "fmi2SetupExperiment"))(c, 0, 0.0, 0.0, 0, 0.0) ||
        ((CompT)sym(lib, "fmi2EnterInitializationMode"))(c) ||
        ((CompT)sym(lib, "fmi2ExitInitializationMode"))(c))
        return 3;
    DoStepT step = (DoStepT)sym(lib, "fmi2DoStep");
    double t = 0.0;
    for (long r = 0; r < repeats; r++) {
        struct timespec a, b;
        clock_gettime(CLOCK_MONOTONIC, &a);
        for (long k = 0; k < n; k++) {
            if (step(c, t, h, 1) != 0) return 3;
            t += h;
        }
        clock_gettime(CLOCK_MONOTONIC, &b);
        printf("%.3f\n", ((b.tv_sec - a.tv_sec) * 1e9 + (b.tv_nsec - a.tv_nsec)) / n);
    }
    return 0;
}
