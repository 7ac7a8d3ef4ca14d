#include "core/expression.hpp"

#include <muParser.h>

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include "core/suggest.hpp"

namespace hencky {

struct Expression::Compiled {
  double x = 0, y = 0, z = 0, t = 0, T = 0;  // the parser holds pointers to these
  mu::Parser parser;
  Compiled() = default;
  Compiled(const Compiled&) = delete;
  Compiled& operator=(const Compiled&) = delete;
};

namespace {

double natural_log(double v) {
  return std::log(v);
}

const std::vector<std::string>& known_names() {
  static const std::vector<std::string> names = {
      "x",    "y",   "z",   "t",  "sin",   "cos",  "tan", "asin", "acos", "atan", "sinh", "cosh",
      "tanh", "exp", "log", "ln", "log10", "sqrt", "abs", "min",  "max",  "_pi",  "_e"};
  return names;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// The whole text as a plain number ("2.1e11", "-3", "+0.5"), else false.
bool as_number(const std::string& text, double& value) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto [p, ec] = std::from_chars(b, e, value);
  return ec == std::errc() && p == e;
}

std::string format_double(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// Position of a lone '=' (assignment in muparser), or npos.
std::size_t find_assignment(const std::string& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '=') continue;
    const bool after_op =
        i > 0 && (s[i - 1] == '=' || s[i - 1] == '<' || s[i - 1] == '>' || s[i - 1] == '!');
    const bool before_eq = i + 1 < s.size() && s[i + 1] == '=';
    if (!after_op && !before_eq) return i;
    if (before_eq) ++i;  // skip "=="
  }
  return std::string::npos;
}

}  // namespace

std::unique_ptr<Expression::Compiled> Expression::compile(const std::string& text, bool with_T) {
  auto c = std::make_unique<Compiled>();
  c->parser.DefineVar("x", &c->x);
  c->parser.DefineVar("y", &c->y);
  c->parser.DefineVar("z", &c->z);
  c->parser.DefineVar("t", &c->t);
  if (with_T) c->parser.DefineVar("T", &c->T);
  // The contract's log is the natural logarithm whatever this muparser's built-in does.
  c->parser.DefineFun("log", natural_log);
  c->parser.DefineFun("ln", natural_log);
  // muparser 2.3.3 defines _pi as 3.141592653589 (12 digits): use the full double values.
  c->parser.DefineConst("_pi", std::numbers::pi);
  c->parser.DefineConst("_e", std::numbers::e);
  c->parser.SetExpr(text);
  return c;
}

Expression::Expression() : text_("0") {}

Expression::Expression(double value) : value_(value), text_(format_double(value)) {}

Expression::Expression(const Expression& other)
    : compiled_(other.compiled_ ? compile(other.text_, other.with_T_)
                                : nullptr),  // own parser, own variables
      value_(other.value_),
      uses_t_(other.uses_t_),
      uses_xyz_(other.uses_xyz_),
      uses_T_(other.uses_T_),
      with_T_(other.with_T_),
      text_(other.text_),
      where_(other.where_) {}

Expression& Expression::operator=(const Expression& other) {
  if (this != &other) {
    Expression copy(other);
    *this = std::move(copy);
  }
  return *this;
}

Expression::Expression(Expression&& other) noexcept = default;
Expression& Expression::operator=(Expression&& other) noexcept = default;
Expression::~Expression() = default;

Expression Expression::parse(const std::string& raw, const SourceLocation& where,
                             Variables variables) {
  Expression e;
  e.where_ = where;
  e.text_ = raw;
  e.with_T_ = variables == Variables::with_temperature;
  const char* variable_names = e.with_T_ ? "x, y, z, t, T" : "x, y, z, t";
  const std::string text = trim(raw);
  if (text.empty())
    throw InputError(where, std::string("expected a number or an expression in ") + variable_names +
                                ", found an empty string");

  double v = 0;
  if (as_number(text, v)) {
    if (!std::isfinite(v))
      throw InputError(where, "expected a finite number, found '" + text + "'");
    e.value_ = v;
    return e;
  }

  if (const auto p = find_assignment(text); p != std::string::npos)
    throw InputError(where, "invalid expression \"" + text + "\": '=' at position " +
                                std::to_string(p) + " is not allowed; use '==' to compare");

  std::unique_ptr<Compiled> c;
  double value = 0;
  try {
    c = compile(text, e.with_T_);
    value = c->parser.Eval();
    if (c->parser.GetNumResults() != 1)
      throw InputError(where, "invalid expression \"" + text + "\": it gives " +
                                  std::to_string(c->parser.GetNumResults()) +
                                  " comma-separated values, expected a single value");
    for (const auto& used : c->parser.GetUsedVar()) {
      if (used.first == "t")
        e.uses_t_ = true;
      else if (used.first == "T")
        e.uses_T_ = true;
      else
        e.uses_xyz_ = true;
    }
  } catch (const mu::Parser::exception_type& err) {
    std::string msg = "invalid expression \"" + text + "\": " + err.GetMsg();
    if (err.GetCode() == mu::ecUNASSIGNABLE_TOKEN) {  // unknown name
      const std::string hint = did_you_mean(err.GetToken(), known_names());
      if (!hint.empty()) msg += " " + hint;
      msg += std::string(" (variables: ") + variable_names +
             "; functions: sin cos tan asin acos atan sinh cosh tanh exp "
             "log ln log10 sqrt abs min max; constants: _pi, _e)";
    }
    throw InputError(where, msg);
  }

  if (!e.uses_t_ && !e.uses_xyz_ && !e.uses_T_) {  // fold a constant expression
    if (!std::isfinite(value))
      throw InputError(where, "the expression \"" + text + "\" evaluates to " +
                                  format_double(value) + ", expected a finite value");
    e.value_ = value;
    return e;
  }
  e.compiled_ = std::move(c);
  return e;
}

double Expression::operator()(double x, double y, double z, double t) const {
  if (!compiled_) return value_;
  compiled_->x = x;
  compiled_->y = y;
  compiled_->z = z;
  compiled_->t = t;
  try {
    return compiled_->parser.Eval();
  } catch (const mu::Parser::exception_type& err) {  // not expected after parse() succeeded
    throw InputError(where_, "cannot evaluate \"" + text_ + "\": " + err.GetMsg());
  }
}

double Expression::operator()(double x, double y, double z, double t, double T) const {
  if (compiled_) compiled_->T = T;
  return (*this)(x, y, z, t);
}

double Expression::eval_checked(double x, double y, double z, double t, const char* what) const {
  const double v = (*this)(x, y, z, t);
  if (std::isfinite(v)) return v;
  std::string msg =
      std::string(what && *what ? what : "value") + ": \"" + text_ + "\" gives " + format_double(v);
  if (compiled_)
    msg += " at x=" + format_double(x) + ", y=" + format_double(y) + ", z=" + format_double(z) +
           ", t=" + format_double(t);
  throw InputError(where_, msg + "; expected a finite value");
}

}  // namespace hencky
