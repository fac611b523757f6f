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
 */
#include <Python.h>
#include <dlfcn.h>
#include <stdio.h>

#ifndef GEAR_DYN_LIBPYTHON
#error "GEAR_DYN_LIBPYTHON (soname of libpython) must be defined"
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
