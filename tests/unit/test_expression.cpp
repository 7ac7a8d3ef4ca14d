// Expression (core/expression.hpp) and the suggestion helpers (core/suggest.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "core/expression.hpp"
#include "core/suggest.hpp"

namespace hencky {
namespace {

const SourceLocation here{"case.yaml", 7, 15, "boundary[1].pressure"};

Expression P(const std::string& text) {
  return Expression::parse(text, here);
}

/// The InputError message of parsing `text`, or "" when it parses.
std::string parse_error(const std::string& text) {
  try {
    P(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool mentions(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(Expression, Numbers) {
  for (auto [text, value] : std::vector<std::pair<std::string, double>>{{"2.1e11", 2.1e11},
                                                                        {"1.0e-6", 1e-6},
                                                                        {"20", 20},
                                                                        {"-3.5", -3.5},
                                                                        {"+4", 4},
                                                                        {" 7 ", 7}}) {
    const Expression e = P(text);
    EXPECT_TRUE(e.is_constant()) << text;
    EXPECT_FALSE(e.depends_on_time()) << text;
    EXPECT_DOUBLE_EQ(e(1, 2, 3, 4), value) << text;
    EXPECT_EQ(e.text(), text);
  }
  EXPECT_DOUBLE_EQ(Expression()(1, 1, 1, 1), 0.0);
  EXPECT_DOUBLE_EQ(Expression(2.5)(1, 1, 1, 1), 2.5);
  EXPECT_TRUE(Expression(2.5).is_constant());
}

TEST(Expression, Arithmetic) {
  EXPECT_DOUBLE_EQ(P("1 + 2*3^2")(0, 0, 0, 0), 19.0);
  EXPECT_DOUBLE_EQ(P("(1 + 2)*3 - 4/8")(0, 0, 0, 0), 8.5);
  EXPECT_DOUBLE_EQ(P("2^3^2")(0, 0, 0, 0), 512.0);  // right associative
  EXPECT_DOUBLE_EQ(P("200e6*t")(0, 0, 0, 0.25), 50e6);
}

TEST(Expression, ComparisonsAndTernary) {
  const Expression e = P("t <= 1 ? 170e6*t : 170e6*(2 - t)");
  EXPECT_TRUE(e.depends_on_time());
  EXPECT_FALSE(e.depends_on_position());
  EXPECT_DOUBLE_EQ(e(0, 0, 0, 0.5), 85e6);
  EXPECT_DOUBLE_EQ(e(0, 0, 0, 1.0), 170e6);
  EXPECT_DOUBLE_EQ(e(0, 0, 0, 1.5), 85e6);
  const Expression nested = P("x < 0 ? -1 : x == 0 ? 0 : 1");
  EXPECT_DOUBLE_EQ(nested(-2, 0, 0, 0), -1.0);
  EXPECT_DOUBLE_EQ(nested(0, 0, 0, 0), 0.0);
  EXPECT_DOUBLE_EQ(nested(3, 0, 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(P("x > 1")(2, 0, 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(P("x >= 1 && y != 2")(1, 2, 0, 0), 0.0);
  EXPECT_DOUBLE_EQ(P("x < 1 || y == 2")(1, 2, 0, 0), 1.0);
}

TEST(Expression, Functions) {
  const double pi = std::numbers::pi;
  auto c = [](const std::string& s) { return P(s)(0, 0, 0, 0); };
  EXPECT_NEAR(c("sin(_pi/2)"), 1.0, 1e-15);
  EXPECT_NEAR(c("cos(_pi)"), -1.0, 1e-15);
  EXPECT_NEAR(c("tan(_pi/4)"), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(c("_e"), std::numbers::e);
  EXPECT_NEAR(c("asin(1)"), pi / 2, 1e-15);
  EXPECT_NEAR(c("acos(-1)"), pi, 1e-15);
  EXPECT_NEAR(c("atan(1)"), pi / 4, 1e-15);
  EXPECT_NEAR(c("sinh(1)"), std::sinh(1.0), 1e-15);
  EXPECT_NEAR(c("cosh(1)"), std::cosh(1.0), 1e-15);
  EXPECT_NEAR(c("tanh(1)"), std::tanh(1.0), 1e-15);
  EXPECT_NEAR(c("exp(1)"), std::numbers::e, 1e-15);
  EXPECT_NEAR(c("sqrt(16)"), 4.0, 1e-15);
  EXPECT_DOUBLE_EQ(c("abs(-3)"), 3.0);
  EXPECT_DOUBLE_EQ(c("min(2, 3)"), 2.0);
  EXPECT_DOUBLE_EQ(c("max(2, 3, 1)"), 3.0);
  EXPECT_DOUBLE_EQ(c("_pi"), pi);
  EXPECT_TRUE(P("2*_pi").is_constant());
}

TEST(Expression, LogIsNatural) {
  auto c = [](const std::string& s) { return P(s)(0, 0, 0, 0); };
  EXPECT_NEAR(c("log(_e)"), 1.0, 1e-15);
  EXPECT_NEAR(c("log(exp(2.5))"), 2.5, 1e-14);
  EXPECT_NEAR(c("log(1000)"), std::log(1000.0), 1e-13);
  EXPECT_NEAR(c("ln(_e)"), 1.0, 1e-15);
  EXPECT_NEAR(c("log10(1000)"), 3.0, 1e-15);
  EXPECT_NEAR(P("log(x)")(10, 0, 0, 0), std::log(10.0), 1e-15);
}

TEST(Expression, VariableBinding) {
  const Expression e = P("x + 10*y + 100*z + 1000*t");
  EXPECT_FALSE(e.is_constant());
  EXPECT_TRUE(e.depends_on_time());
  EXPECT_TRUE(e.depends_on_position());
  EXPECT_DOUBLE_EQ(e(1, 2, 3, 4), 4321.0);
  EXPECT_DOUBLE_EQ(e(4, 3, 2, 1), 1234.0);
  const Expression space = P("20 + 300*x/0.2");
  EXPECT_FALSE(space.depends_on_time());
  EXPECT_DOUBLE_EQ(space(0.1, 0, 0, 0), 170.0);
  EXPECT_EQ(space.where().key, "boundary[1].pressure");
}

TEST(Expression, CopiesAreIndependent) {
  auto original = std::make_unique<Expression>(P("x*t + y"));
  const Expression copy(*original);
  Expression assigned;
  assigned = *original;
  original.reset();  // the copies must not point into the destroyed object
  EXPECT_DOUBLE_EQ(copy(2, 1, 0, 3), 7.0);
  EXPECT_DOUBLE_EQ(assigned(2, 1, 0, 3), 7.0);
  EXPECT_EQ(copy.text(), "x*t + y");
  EXPECT_TRUE(copy.depends_on_time());

  // Evaluating one copy does not disturb the other; growing a vector moves/copies safely.
  std::vector<Expression> v;
  for (int i = 0; i < 20; ++i) v.push_back(P(std::to_string(i) + " + x"));
  std::vector<Expression> w = v;
  v.clear();
  for (int i = 0; i < 20; ++i) EXPECT_DOUBLE_EQ(w[i](0.5, 0, 0, 0), i + 0.5);

  Expression moved = std::move(w[3]);
  EXPECT_DOUBLE_EQ(moved(1, 0, 0, 0), 4.0);
  Expression self = P("x");
  const Expression& alias = self;
  self = alias;  // self assignment
  EXPECT_DOUBLE_EQ(self(5, 0, 0, 0), 5.0);
}

TEST(Expression, SyntaxErrorsNameTheLocation) {
  const std::string m = parse_error("1 + ");
  EXPECT_TRUE(mentions(m, "case.yaml:7:15")) << m;
  EXPECT_TRUE(mentions(m, "'boundary[1].pressure'")) << m;
  EXPECT_TRUE(mentions(m, "\"1 +\"")) << m;
  EXPECT_TRUE(mentions(m, "Unexpected end of expression")) << m;  // muparser's own message
  EXPECT_TRUE(mentions(parse_error("(x + 1"), "parenthesis")) << parse_error("(x + 1");
}

TEST(Expression, UnknownNamesGetSuggestions) {
  std::string m = parse_error("sn(x)");
  EXPECT_TRUE(mentions(m, "Unexpected token \"sn\"")) << m;
  EXPECT_TRUE(mentions(m, "did you mean 'sin'?")) << m;
  m = parse_error("200e6*tt");
  EXPECT_TRUE(mentions(m, "did you mean 't'?")) << m;
  m = parse_error("u + 1");
  EXPECT_TRUE(mentions(m, "Unexpected token \"u\"")) << m;
  EXPECT_TRUE(mentions(m, "variables: x, y, z, t")) << m;
  m = parse_error("pi*x");
  EXPECT_TRUE(mentions(m, "did you mean '_pi'?")) << m;
}

TEST(Expression, OtherErrors) {
  EXPECT_TRUE(mentions(parse_error(""), "empty")) << parse_error("");
  EXPECT_TRUE(mentions(parse_error("x = 1"), "use '=='")) << parse_error("x = 1");
  EXPECT_EQ(parse_error("x == 1"), "");
  EXPECT_EQ(parse_error("x <= 1"), "");
  EXPECT_TRUE(mentions(parse_error("1, 2"), "single value")) << parse_error("1, 2");
  EXPECT_TRUE(mentions(parse_error("1/0"), "finite")) << parse_error("1/0");
  EXPECT_TRUE(mentions(parse_error("sqrt(-1)"), "finite")) << parse_error("sqrt(-1)");
  EXPECT_EQ(parse_error("1/x"), "");  // infinite at the origin only: fine at parse time
}

TEST(Expression, EvalChecked) {
  const Expression e = P("sqrt(x)");
  EXPECT_DOUBLE_EQ(e.eval_checked(4, 0, 0, 0, "pressure"), 2.0);
  try {
    e.eval_checked(-1, 0, 0, 0.5, "pressure");
    FAIL() << "expected an InputError";
  } catch (const InputError& err) {
    const std::string m = err.what();
    EXPECT_TRUE(mentions(m, "case.yaml:7:15")) << m;
    EXPECT_TRUE(mentions(m, "pressure")) << m;
    EXPECT_TRUE(mentions(m, "\"sqrt(x)\"")) << m;
    EXPECT_TRUE(mentions(m, "x=-1")) << m;
    EXPECT_TRUE(mentions(m, "t=0.5")) << m;
  }
  EXPECT_THROW(P("1/x").eval_checked(0, 0, 0, 0, "traction"), InputError);
  EXPECT_TRUE(std::isinf(P("1/x")(0, 0, 0, 0)));  // operator() does not check
}

TEST(ExpressionSuggest, Closest) {
  const std::vector<std::string> keys = {"title",    "mesh",   "materials", "temperature",
                                         "boundary", "solver", "output"};
  EXPECT_EQ(closest("materails", keys), "materials");
  EXPECT_EQ(closest("MESH", keys), "mesh");
  EXPECT_EQ(closest("boundry", keys), "boundary");
  EXPECT_EQ(closest("solvr", keys), "solver");
  EXPECT_EQ(closest("xyzzy", keys), "");
  EXPECT_EQ(closest("q", {"E"}), "");
  EXPECT_EQ(closest("e", {"E", "nu"}), "E");
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(did_you_mean("outptu", keys), "did you mean 'output'?");
  EXPECT_EQ(did_you_mean("zzzzzz", keys), "");
  EXPECT_EQ(name_list({"a", "b"}), "'a', 'b'");
  EXPECT_EQ(name_list({"a", "b", "c"}, 2), "'a', 'b' ... and 1 more");
  EXPECT_EQ(suggestion("inenr", {"inner", "outer"}, "regions"),
            "did you mean 'inner'? valid regions: 'inner', 'outer'");
  EXPECT_EQ(suggestion("zzz", {"inner"}, "regions"), "valid regions: 'inner'");
}

}  // namespace
}  // namespace hencky
