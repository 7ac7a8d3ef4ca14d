// Expressions of x, y, z, t (and T where the case allows it) through muparser
// (core/expression), on any text: parsing, then evaluation at a few points.
#include <string>

#include "core/expression.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  const std::string text(fuzz::text_of(data, size));
  const std::string file = "fuzz.yaml";
  const SourceLocation where{file, 1, 1, "boundary[0].pressure"};
  for (const auto vars : {Expression::Variables::xyzt, Expression::Variables::with_temperature}) {
    fuzz::expect_input_error_or_success(file, [&] {
      const Expression e = Expression::parse(text, where, vars);
      Expression copy = e;  // each thread of an analysis evaluates its own copy
      copy(1, -2, 3.5, 0.25, 300);
      copy(-1e300, 0, 1e-300, 1, -273.15);
      e.eval_checked(0.5, 0.5, 0.5, 1, "pressure");
    });
  }
  return 0;
}
