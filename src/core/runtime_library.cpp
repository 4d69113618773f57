// dlopen + dlsym for the libraries loaded on first use (core/runtime_library.hpp says why).
#include "core/runtime_library.hpp"

#include <dlfcn.h>

#include <cstring>

namespace microbrdf::detail {

std::string load_runtime_library(const char* soname, const char* package,
                                 std::initializer_list<RuntimeSymbol> symbols) {
  void* h = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
  if (h == nullptr) {
    const char* e = dlerror();
    return std::string(soname) + " cannot be loaded (" + (e ? e : "unknown error") + "); install " +
           package;
  }
  std::string missing;
  for (const RuntimeSymbol& s : symbols) {
    void* p = dlsym(h, s.name);
    if (p == nullptr) missing += std::string(missing.empty() ? "" : ", ") + s.name;
    // (POSIX: a function's address from dlsym may be stored through a data pointer.)
    std::memcpy(s.slot, &p, sizeof p);
  }
  if (!missing.empty()) {
    for (const RuntimeSymbol& s : symbols) std::memset(s.slot, 0, sizeof(void*));  // none kept
    dlclose(h);
    return std::string(soname) + " lacks " + missing +
           " (another version than microbrdf was built with?); install " + package;
  }
  return "";
}

}  // namespace microbrdf::detail
