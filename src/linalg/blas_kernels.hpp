#pragma once
// OpenBLAS picks its kernels from the CPU's model number. Debian 12's OpenBLAS (0.3.21) does not
// know the newest Intel models (Sapphire/Emerald Rapids: family 6, model 143, 207) and falls back
// to its oldest x86-64 kernels ("Prescott", SSE3): dgemm then runs at 8.8 Gflop/s on a CPU that
// gives 43 with the Skylake-X kernels, and CHOLMOD's factorizations take 2-5 times as long
// (docs/performance.md, "The BLAS kernels"). The kernels are chosen when the library is loaded,
// before main(); OPENBLAS_CORETYPE overrides the choice, so a process that finds the fallback on a
// CPU with AVX2 or AVX-512 starts itself again with that variable set.
#include <string>

namespace hencky {

/// What OpenBLAS chose ("" when the BLAS in use is not OpenBLAS), and the core type to ask for
/// instead ("" when its choice fits the CPU: it uses AVX2 or better, or the CPU has neither).
struct BlasKernels {
  std::string chosen, better;
};
BlasKernels blas_kernels();

/// At the start of main: when OpenBLAS runs its fallback kernels on a CPU with AVX2 or AVX-512,
/// execs /proc/self/exe again with OPENBLAS_CORETYPE set (once: HENCKY_BLAS_RESTARTED marks the
/// second start). Nothing happens when OPENBLAS_CORETYPE is already set (the user's choice) or
/// HENCKY_BLAS_KERNELS=keep. Returns only when it did not exec.
void restart_with_better_blas_kernels(char** argv);

/// The line for hencky.log when the process was started again by
/// restart_with_better_blas_kernels ("" otherwise).
std::string blas_kernels_note();

}  // namespace hencky
