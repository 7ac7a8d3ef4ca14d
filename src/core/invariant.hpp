#pragma once
// Programming errors: one check for every build type (as MFEM_VERIFY and mooseAssert are).
// A broken invariant is hencky's fault, never the user's: it throws InternalError, which the
// command line reports with exit status 3 ("internal error") and the file and line of the
// check. User input is checked with InputError (core/error.hpp), never with this.
//
//   HENCKY_VERIFY(i <= j, "upper triangle only");
//
// The condition is evaluated in Release builds too; keep it off the innermost loops (an
// element's or a point's), where a check that cannot fail costs more than it tells.
#include <stdexcept>
#include <string>

namespace hencky {

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] inline void invariant_failed(const char* condition, const std::string& message,
                                          const char* file, int line) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": " + message + " (" +
                      condition + ")");
}

}  // namespace hencky

#define HENCKY_VERIFY(condition, message)                                       \
  do {                                                                          \
    if (!(condition)) ::hencky::invariant_failed(#condition, (message), __FILE__, __LINE__); \
  } while (false)
