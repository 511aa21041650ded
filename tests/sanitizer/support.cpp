// Linked into every executable of a DRAPE_SANITIZE build (drape, drape_tests, each *_gl_test), so that the
// sanitizers behave the same under ctest, when a test reruns itself under xvfb-run, when a test runs the
// drape binary, and when a person runs a binary by hand. $ASAN_OPTIONS, $LSAN_OPTIONS and $UBSAN_OPTIONS are
// read after these defaults and override them.
//
// LeakSanitizer stays on with no suppressions: any leak it reports fails the test. Two measures, each for
// one known problem outside this project, keep its reports true:
//
// 1. intercept_tls_get_addr=0. GCC 12's (and LLVM 14's) sanitizer runtime mistakes some dynamic TLS blocks
//    for a pre-2.25 glibc layout and reads a bogus range from them; the leak check at exit then dies with
//    "Tracer caught signal 11" (drape render on llvmpipe hits it every time). With the flag the runtime does
//    not track dynamic TLS: a pointer held only there would show as a leak (a false alarm), never hide one.
//
// 2. Mesa's DRI driver (*_dri.so, llvmpipe's swrast_dri.so here) stays loaded until exit. libGLX_mesa
//    dlclose()s it when a GLFW window's display closes (the viewer tests under Xvfb); what the driver's
//    globals still point to is then unreachable at exit and was reported as leaked, from frames in an
//    unmapped module that no suppression can match (they print as "<unknown module>" or as a wrong module).
//    With the driver kept, those tests report no leak at all. Every other library unloads as usual.
#include <dlfcn.h>
#include <link.h>

#include <string_view>

extern "C" const char* __asan_default_options() {
  return "intercept_tls_get_addr=0";
}

// A UB report shows where it happened; the build's -fno-sanitize-recover=all makes it fail the process.
extern "C" const char* __ubsan_default_options() {
  return "print_stacktrace=1:halt_on_error=1";
}

namespace {

bool isMesaDriDriver(void* handle) {
  link_map* map = nullptr;
  if (::dlinfo(handle, RTLD_DI_LINKMAP, &map) != 0 || map == nullptr || map->l_name == nullptr) return false;
  const std::string_view path(map->l_name);
  const std::string_view name = path.substr(path.rfind('/') + 1);  // npos + 1 == 0: no directory
  return name.ends_with("_dri.so");
}

}  // namespace

// Interposes libc's dlclose for the whole process (the executable exports it: -Wl,--export-dynamic-symbol).
extern "C" int dlclose(void* handle) noexcept {
  if (isMesaDriDriver(handle)) return 0;  // kept loaded, see 2. above
  using Close = int (*)(void*);
  static const Close next = reinterpret_cast<Close>(::dlsym(RTLD_NEXT, "dlclose"));
  return next(handle);
}
