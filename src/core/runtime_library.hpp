#pragma once
// Optional shared libraries loaded when a command first needs them, not at process start.
//
// Why: every shared library a binary links is mapped and relocated before main(), and some
// bring long chains with them (libhdf5: libcurl with its TLS and Kerberos stack; Cairo: X11,
// fontconfig, freetype; libtiff: its codecs). Measured on a trivial program linked with the same
// libraries as the CLI, they cost about 14 ms of a 27 ms start, paid by every `microbrdf`
// process, while only the .datx reader, the TIFF reader and the plots use them. So they are
// loaded with dlopen, by the soname the build found, when first used (docs/benchmarks.md).
//
// How a library is declared (surface/hdf5_runtime.hpp, surface/tiff_runtime.hpp,
// plot/cairo_runtime.hpp): its header is included for types and constants; each function the
// project calls is listed once in an X-macro list, which declares a pointer of the same name and
// type in namespace microbrdf. Unqualified calls inside namespace microbrdf find that pointer
// before the global function (C++ name lookup stops at the innermost scope that has the name, and
// a variable turns argument-dependent lookup off), so call sites read as the library documents
// them. The library is not linked: a call that bypasses the list is an undefined reference at
// link time, so the list cannot fall behind its users.
#include <initializer_list>
#include <string>

namespace microbrdf::detail {

struct RuntimeSymbol {
  const char* name;  ///< symbol name for dlsym
  void* slot;        ///< address of the pointer variable to fill
};

/// Loads `soname` (RTLD_NOW | RTLD_LOCAL, kept loaded for the process's lifetime) and stores the
/// address of each symbol in its slot. Returns "" on success, else a message naming the soname,
/// the cause and `package` (what to install).
std::string load_runtime_library(const char* soname, const char* package,
                                 std::initializer_list<RuntimeSymbol> symbols);

}  // namespace microbrdf::detail

/// In namespace microbrdf: a pointer named and typed like the global function f.
#define MICROBRDF_RUNTIME_DECLARE(f) inline decltype(&::f) f = nullptr;
/// An entry of load_runtime_library's list for the pointer declared above.
#define MICROBRDF_RUNTIME_SYMBOL(f) ::microbrdf::detail::RuntimeSymbol{#f, &::microbrdf::f},
