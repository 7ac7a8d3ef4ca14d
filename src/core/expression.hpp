#pragma once
// A scalar input value: a number, or a muparser expression in x, y, z (coordinates) and
// t (pseudo-time), as the case-file contract allows for every load value.
#include <memory>
#include <string>

#include "core/error.hpp"

namespace hencky {

/// A scalar that is either a number or a compiled muparser expression in x, y, z, t.
///
/// Syntax (CASE_FORMAT.md): `+ - * / ^`, comparisons `< <= > >= == !=`, `&& ||`, `a ? b : c`,
/// the functions `sin cos tan asin acos atan sinh cosh tanh exp log ln log10 sqrt abs min max`
/// (`log` is the NATURAL logarithm, like `ln`) and the constants `_pi`, `_e` (full double
/// precision; muparser 2.3.3's own `_pi` has only 12 digits). muparser's
/// other built-ins (`log2 sign rint sum avg`) also work but are not part of the contract.
///
/// An expression that uses none of x, y, z, t is folded to its value at parse time and then
/// is_constant() is true. Where the case allows it (heat.source), an expression may also use
/// the temperature T (parse with Variables::with_temperature).
///
/// Thread safety: evaluating a non-constant Expression writes to variable storage and to the
/// muparser evaluation stack owned by the object, so one object must not be evaluated from
/// two threads at the same time. Give every thread its own copy (copies are independent:
/// each one compiles its own parser bound to its own variables). Constant expressions are
/// safe to evaluate concurrently.
class Expression {
 public:
  Expression();                       ///< the constant 0
  explicit Expression(double value);  ///< a constant
  Expression(const Expression& other);
  Expression& operator=(const Expression& other);
  Expression(Expression&& other) noexcept;
  Expression& operator=(Expression&& other) noexcept;
  ~Expression();

  enum class Variables { xyzt, with_temperature };

  /// Parses a number or compiles an expression, and evaluates it once at x=y=z=t=0 (muparser
  /// reports many errors only at evaluation). A malformed expression, an unknown variable or
  /// function, an assignment `=` or a list of values is an InputError at `where` that quotes
  /// the expression and muparser's message. A constant (no x, y, z, t) that is not finite is
  /// an error too; a non-constant one may legitimately be inf/NaN at the origin.
  static Expression parse(const std::string& text, const SourceLocation& where,
                          Variables variables = Variables::xyzt);

  /// The value at (x, y, z, t). Not thread-safe (see above). May be NaN or inf.
  double operator()(double x, double y, double z, double t) const;
  /// The value at (x, y, z, t) and temperature T (Variables::with_temperature; T is ignored
  /// otherwise). Not thread-safe.
  double operator()(double x, double y, double z, double t, double T) const;

  /// The value, or an InputError at where() when it is NaN or infinite; `what` says what the
  /// value is for (e.g. "pressure"), the message gives the point and the time.
  double eval_checked(double x, double y, double z, double t, const char* what) const;

  bool is_constant() const { return compiled_ == nullptr; }
  bool depends_on_time() const { return uses_t_; }
  bool depends_on_position() const { return uses_xyz_; }
  bool depends_on_temperature() const { return uses_T_; }
  /// The text as written in the case file (for a constant built from a double: that number).
  const std::string& text() const { return text_; }
  const SourceLocation& where() const { return where_; }

 private:
  struct Compiled;  // muparser parser + its variables, never moved once built
  static std::unique_ptr<Compiled> compile(const std::string& text, bool with_T);

  std::unique_ptr<Compiled> compiled_;  // null for a constant
  double value_ = 0.0;                  // the value when constant
  bool uses_t_ = false;
  bool uses_xyz_ = false;
  bool uses_T_ = false;
  bool with_T_ = false;  // T is a variable (Variables::with_temperature)
  std::string text_;
  SourceLocation where_;
};

}  // namespace hencky
