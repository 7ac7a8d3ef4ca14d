#pragma once
// One exception type for errors in the user's input (exit status 1). Programming errors are
// assertions, not exceptions of this type.
#include <stdexcept>
#include <string>

namespace hencky {

struct SourceLocation {
  std::string file;  ///< file the error is about (case file, mesh, temperature table)
  int line = 0;      ///< 1-based, 0 when unknown
  int column = 0;    ///< 1-based, 0 when unknown
  std::string key;   ///< dotted key path in the case file, e.g. "boundary[2].pressure"
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, const std::string& message)
      : std::runtime_error(format(where, message)), where_(std::move(where)), message_(message) {}
  explicit InputError(const std::string& message) : InputError(SourceLocation{}, message) {}

  const SourceLocation& where() const { return where_; }
  const std::string& message() const { return message_; }

  /// "file:line:column: key: message" with the parts that are known.
  static std::string format(const SourceLocation& w, const std::string& message) {
    std::string s;
    if (!w.file.empty()) {
      s.append(w.file);
      if (w.line > 0) {
        s.append(1, ':').append(std::to_string(w.line));
        if (w.column > 0) s.append(1, ':').append(std::to_string(w.column));
      }
      s.append(": ");
    }
    if (!w.key.empty()) s.append(1, '\'').append(w.key).append("': ");
    s.append(message);
    return s;
  }

 private:
  SourceLocation where_;
  std::string message_;
};

/// An output file could not be written (a full disk, a file system that turned read-only, a
/// file size limit): the run stops with status 2 and keeps the steps written before.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A step (or the whole analysis) could not be completed numerically: not an input error.
class SolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A back end could not solve the linear system: the matrix is singular (a body not held) or
/// not positive definite (a negative tangent), an iterative solve diverged, or the back end
/// failed otherwise (out of memory). The step control
/// maps these to its messages (solve/step_control.cpp).
class LinearSystemError : public SolveError {
 public:
  enum class Kind { singular, not_positive_definite, diverged, failed };
  /// `equation`: the unknown, in the system's numbering, where a factorization met a pivot
  /// that is not positive (-1: unknown), for the message to say where.
  LinearSystemError(Kind kind, const std::string& what, long equation = -1)
      : SolveError(what), kind_(kind), equation_(equation) {}
  Kind kind() const { return kind_; }
  long equation() const { return equation_; }

 private:
  Kind kind_;
  long equation_;
};

/// The linear solver cannot be set up with the options it was given (a PETSc option that does
/// not apply here): the user's input, not the matrix.
class SolverOptionsError : public SolveError {
 public:
  using SolveError::SolveError;
};

}  // namespace hencky
