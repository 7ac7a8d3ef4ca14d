#pragma once
// What the tests of a material point share (test_plastic_point.cpp, test_kinematic.cpp): a
// property table of one value, a steel, a linear hardening curve, a tangent by differences.
#include "core/types.hpp"
#include "material/elastic.hpp"
#include "spec/case.hpp"

namespace hencky::point_support {

inline PropertyTable constant(double v) {
  PropertyTable p;
  p.value = {v};
  return p;
}

inline const ElasticConstants steel{2.0e11, 0.3, 0.0};

inline PlasticitySpec linear_spec(double yield, double hardening) {
  PlasticitySpec s;
  s.curve.kind = CurveSpec::Kind::linear;
  s.curve.yield = constant(yield);
  s.curve.hardening = constant(hardening);
  return s;
}

/// dσ/dx of a point update `sigma(x)` by central differences with step h, column by column:
/// what a consistent tangent is checked against.
template <class F>
Mat6 central_differences(F&& sigma, const Voigt& x, double h = 1e-8) {
  Mat6 fd;
  for (int j = 0; j < 6; ++j) {
    Voigt xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    fd.col(j) = (sigma(xp) - sigma(xm)) / (2 * h);
  }
  return fd;
}

}  // namespace hencky::point_support
