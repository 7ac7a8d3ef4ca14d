#include "linalg/blas_kernels.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace hencky {

namespace {

/// OpenBLAS's x86-64 cores without AVX2: the fallback of an unknown model and the old CPUs'.
bool without_avx2(std::string core) {
  std::transform(core.begin(), core.end(), core.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* old : {"prescott", "core2", "penryn", "dunnington", "nehalem", "atom",
                          "sandybridge", "katmai", "coppermine", "northwood", "banias", "yonah"})
    if (core == old) return true;
  return false;
}

}  // namespace

BlasKernels blas_kernels() {
  BlasKernels k;
  // Looked up at run time: the BLAS behind libblas.so.3 is whichever Debian's alternatives
  // point to, and only OpenBLAS has this function.
  using CoreName = char* (*)();
  const auto core_name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (!core_name) return k;
  if (const char* name = core_name()) k.chosen = name;
  // A test hook (tests/cli/cases/65_linear_auto.sh): the core OpenBLAS is said to have chosen
  // at the first start, so that the restart is exercised on CPUs OpenBLAS knows.
  if (const char* said = std::getenv("HENCKY_BLAS_TEST_CHOSEN"); said && !std::getenv("HENCKY_BLAS_RESTARTED"))
    k.chosen = said;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (!without_avx2(k.chosen)) return k;
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl"))
    k.better = "SkylakeX";
  else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    k.better = "Haswell";
#endif
  return k;
}

void restart_with_better_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("HENCKY_BLAS_RESTARTED")) return;
  if (const char* keep = std::getenv("HENCKY_BLAS_KERNELS"); keep && std::string(keep) == "keep")
    return;
  const BlasKernels k = blas_kernels();
  if (k.better.empty()) return;
  setenv("OPENBLAS_CORETYPE", k.better.c_str(), 1);
  setenv("HENCKY_BLAS_RESTARTED", k.chosen.c_str(), 1);
  execv("/proc/self/exe", argv);
  // The exec failed (no /proc): go on with the kernels there are.
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv("HENCKY_BLAS_RESTARTED");
}

std::string blas_kernels_note() {
  const char* before = std::getenv("HENCKY_BLAS_RESTARTED");
  const char* now = std::getenv("OPENBLAS_CORETYPE");
  if (!before || !now) return "";
  return std::string("BLAS: OpenBLAS took its '") + before +
         "' kernels for this CPU (a model it does not know); hencky started again with "
         "OPENBLAS_CORETYPE=" + now + " (now '" + blas_kernels().chosen +
         "'; HENCKY_BLAS_KERNELS=keep or an OPENBLAS_CORETYPE of your own turns this off)";
}

}  // namespace hencky
