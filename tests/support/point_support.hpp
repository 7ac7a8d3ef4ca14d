#pragma once
// What the tests of a material point share (test_plastic_point.cpp, test_kinematic.cpp,
// test_hencky_strain.cpp): a
// property table of one value, a steel, a linear hardening curve, a random Voigt vector, a
// tangent by differences.
#include <random>

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

/// A Voigt vector of components uniform in [−scale, scale].
inline Voigt random_voigt(std::mt19937& g, double scale) {
  std::uniform_real_distribution<double> d(-1, 1);
  Voigt v;
  for (int i = 0; i < 6; ++i) v[i] = scale * d(g);
  return v;
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
