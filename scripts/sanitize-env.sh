# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: the sanitizers' run-time options.
# Every report stops the program (UBSan too: -fno-sanitize-recover), with a symbolized stack.
# LeakSanitizer's suppressions (tests/lsan.supp) name third-party code only; ctest adds them
# to each test itself (CMakeLists.txt), and the slow unwinder to those that start MPI.
_src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
export ASAN_OPTIONS="halt_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$_src/tests/lsan.supp"
unset _src
