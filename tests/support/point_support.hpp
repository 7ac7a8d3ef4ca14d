#pragma once
// What the tests of a material point share (test_plastic_point.cpp, test_kinematic.cpp): a
// property table of one value, a steel, a linear hardening curve.
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

}  // namespace hencky::point_support
