/* A minimal FMI 2.0 Co-Simulation host with no Python in the process: loads an extracted
 * stiction FMU's library, runs it to StopTime in steps of H and prints the value of one output
 * at the end, the mean wall time of a doStep, and the resident memory after CYCLES extra
 * instantiate/free and reset cycles (to show it does not grow). The state saved halfway is
 * serialized, then restored in the same instance and, from its bytes, in a new one: both
 * continue to StopTime and print their value there (they must agree bit for bit).
 * usage: harness UNZIPDIR LIBRARY GUID VR_OUT STOP H CYCLES [VR_IN VALUE] */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef void *C;
typedef void (*Logger)(void *, const char *, int, const char *, const char *, ...);
typedef struct {
    Logger logger;
    void *(*alloc)(size_t, size_t);
    void (*free)(void *);
    void *step_finished;
    void *env;
} Callbacks;

static void logger(void *env, const char *name, int status, const char *cat, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "[%s %d %s] ", name, status, cat);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n");
    va_end(ap);
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static long rss_kb(void) {
    long pages = 0, resident = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f && fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = -1;
    if (f) fclose(f);
    return resident * 4;
}

#define SYM(name) name##_t name = (name##_t)dlsym(lib, #name); if (!name) { fprintf(stderr, "missing %s\n", #name); return 2; }
typedef C (*fmi2Instantiate_t)(const char *, int, const char *, const char *, const Callbacks *, int, int);
typedef void (*fmi2FreeInstance_t)(C);
typedef int (*fmi2SetupExperiment_t)(C, int, double, double, int, double);
typedef int (*fmi2EnterInitializationMode_t)(C);
typedef int (*fmi2ExitInitializationMode_t)(C);
typedef int (*fmi2DoStep_t)(C, double, double, int);
typedef int (*fmi2GetReal_t)(C, const unsigned *, size_t, double *);
typedef int (*fmi2SetReal_t)(C, const unsigned *, size_t, const double *);
typedef int (*fmi2Terminate_t)(C);
typedef int (*fmi2Reset_t)(C);
typedef int (*fmi2GetFMUstate_t)(C, void **);
typedef int (*fmi2SetFMUstate_t)(C, void *);
typedef int (*fmi2FreeFMUstate_t)(C, void **);
typedef int (*fmi2SerializedFMUstateSize_t)(C, void *, size_t *);
typedef int (*fmi2SerializeFMUstate_t)(C, void *, char *, size_t);
typedef int (*fmi2DeSerializeFMUstate_t)(C, const char *, size_t, void **);

int main(int argc, char **argv) {
    if (argc < 8) return 2;
    char uri[4096];
    snprintf(uri, sizeof uri, "file://%s/resources", argv[1]);
    void *lib = dlopen(argv[2], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    SYM(fmi2Instantiate) SYM(fmi2FreeInstance) SYM(fmi2SetupExperiment)
    SYM(fmi2EnterInitializationMode) SYM(fmi2ExitInitializationMode) SYM(fmi2DoStep)
    SYM(fmi2GetReal) SYM(fmi2SetReal) SYM(fmi2Terminate) SYM(fmi2Reset)
    SYM(fmi2GetFMUstate) SYM(fmi2SetFMUstate) SYM(fmi2FreeFMUstate)
    SYM(fmi2SerializedFMUstateSize) SYM(fmi2SerializeFMUstate) SYM(fmi2DeSerializeFMUstate)
    const char *guid = argv[3];
    unsigned vr = (unsigned)atoi(argv[4]);
    double stop = atof(argv[5]), h = atof(argv[6]);
    int cycles = atoi(argv[7]);
    Callbacks cb = {logger, calloc, free, NULL, NULL};
    C c = fmi2Instantiate("harness", 1, guid, uri, &cb, 0, 0);
    if (!c) return 3;
    int bad = 0;
    bad |= fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, stop);
    bad |= fmi2EnterInitializationMode(c);
    if (argc > 9) {
        unsigned in = (unsigned)atoi(argv[8]);
        double u = atof(argv[9]);
        bad |= fmi2SetReal(c, &in, 1, &u);
    }
    bad |= fmi2ExitInitializationMode(c);
    long steps = (long)(stop / h + 0.5);
    double t0 = now();
    long mid = steps / 2;
    for (long k = 0; k < mid && !bad; k++) bad |= fmi2DoStep(c, k * h, h, 1);
    void *state = NULL;
    bad |= fmi2GetFMUstate(c, &state);
    for (long k = mid; k < steps && !bad; k++) bad |= fmi2DoStep(c, k * h, h, 1);
    double elapsed = now() - t0;
    double y = 0.0;
    bad |= fmi2GetReal(c, &vr, 1, &y);
    /* the saved state: its bytes, then continued here and in a new instance */
    size_t size = 0;
    bad |= fmi2SerializedFMUstateSize(c, state, &size);
    char *bytes = malloc(size);
    bad |= fmi2SerializeFMUstate(c, state, bytes, size);
    double y_same = 0.0, y_new = 0.0;
    bad |= fmi2SetFMUstate(c, state);
    for (long k = mid; k < steps && !bad; k++) bad |= fmi2DoStep(c, k * h, h, 1);
    bad |= fmi2GetReal(c, &vr, 1, &y_same);
    bad |= fmi2FreeFMUstate(c, &state);
    C fresh = fmi2Instantiate("fresh", 1, guid, uri, &cb, 0, 0);
    void *copy = NULL;
    if (!fresh) bad = 1;
    if (!bad) bad |= fmi2DeSerializeFMUstate(fresh, bytes, size, &copy);
    if (!bad) bad |= fmi2SetFMUstate(fresh, copy);
    for (long k = mid; k < steps && !bad; k++) bad |= fmi2DoStep(fresh, k * h, h, 1);
    if (!bad) bad |= fmi2GetReal(fresh, &vr, 1, &y_new);
    if (fresh) fmi2FreeFMUstate(fresh, &copy);
    fmi2FreeInstance(fresh);
    free(bytes);
    bad |= fmi2Terminate(c);
    long rss0 = rss_kb();
    for (int k = 0; k < cycles && !bad; k++) {
        bad |= fmi2Reset(c);
        bad |= fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, stop);
        bad |= fmi2EnterInitializationMode(c);
        bad |= fmi2ExitInitializationMode(c);
        C other = fmi2Instantiate("other", 1, guid, uri, &cb, 0, 0);
        if (!other) bad = 1;
        fmi2FreeInstance(other);
    }
    long rss1 = rss_kb();
    fmi2FreeInstance(c);
    printf("status %d\nvalue %.17g\nseconds %.9g\nsteps %ld\nrss_before_kb %ld\nrss_after_kb %ld\n"
           "restored_same %.17g\nrestored_new %.17g\nstate_bytes %zu\n",
           bad, y, elapsed, steps, rss0, rss1, y_same, y_new, size);
    return bad ? 1 : 0;
}
