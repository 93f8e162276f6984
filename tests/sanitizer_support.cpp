// tests/sanitizer_support.cpp: compiled into aniso_tests in the sanitizer build only
// (ANISO_SANITIZE, docs/testing.md, "Sanitizers").
//
// Mesa's GL driver (llvmpipe in swrast_dri.so, loaded by libEGL_mesa through glvnd) keeps a few
// allocations until exit and is unloaded (dlclose) before LeakSanitizer looks at the heap, so its
// leaks show as "<unknown module>" and no suppression can name them. Loading the driver's modules
// once more with RTLD_NODELETE keeps them mapped to the end: their frames then carry the module
// name, and tests/lsan.supp suppresses exactly those modules (and nothing of ours).
#include <dlfcn.h>

#include <initializer_list>

namespace {
struct KeepGlDriverLoaded {
  KeepGlDriverLoaded() {
    for (const char* lib : {"libEGL_mesa.so.0", "/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", "libglapi.so.0"})
      (void)dlopen(lib, RTLD_NOW | RTLD_GLOBAL | RTLD_NODELETE);  // absent: no GL, the GL tests skip
  }
} keep_gl_driver_loaded;
}  // namespace
