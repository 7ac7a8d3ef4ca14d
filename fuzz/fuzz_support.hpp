#pragma once
// What the fuzz targets share: the rule that decides what is a bug.
//
// A reader may refuse its input, with an InputError (core/error.hpp) that names the file it
// was given: that is the documented outcome of bad input (exit status 1). Anything else is a
// bug for libFuzzer to report: a sanitizer finding, a fault, any other exception (it escapes
// LLVMFuzzerTestOneInput, and std::terminate aborts), an input error that does not say which
// file it is about, a time-out or running out of memory.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace hencky::fuzz {

inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Runs `read`; an InputError is a normal outcome when it is about `file` (about some file when
/// `file` is empty: a case names other files, whose errors name them).
/// With HENCKY_FUZZ_SHOW set, prints each input's outcome: for looking at what a corpus covers
/// (fuzz_NAME -runs=0 corpus/NAME).
template <class Read>
void expect_input_error_or_success(const std::string& file, Read&& read) {
  static const bool show = std::getenv("HENCKY_FUZZ_SHOW") != nullptr;
  try {
    read();
    if (show) std::fprintf(stderr, "fuzz: accepted\n");
  } catch (const InputError& e) {
    if (show) std::fprintf(stderr, "fuzz: refused: %s\n", e.what());
    if (file.empty() ? e.where().file.empty() : e.where().file != file) {
      std::fprintf(stderr, "fuzz: an input error about '%s', expected one about '%s':\n%s\n",
                   e.where().file.c_str(), file.c_str(), e.what());
      std::abort();
    }
  }
}

}  // namespace hencky::fuzz
