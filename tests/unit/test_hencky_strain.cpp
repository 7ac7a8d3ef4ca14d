// Hencky's strain for one updated Lagrangian step (fem/hencky_strain.hpp): the tangent dS/dE
// against finite differences (elastic and on the radial return), a rigid rotation that makes no
// strain, coaxial stretches whose logarithmic strains add, and the uniaxial return in one step
// against many.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fem/geometry.hpp"
#include "fem/hencky_strain.hpp"
#include "material/plastic_point.hpp"
#include "point_support.hpp"

namespace hencky {
namespace {

using namespace point_support;

TEST(HenckyStrain, HalfLogDifferenceIsSmoothAcrossEqualArguments) {
  // With a = b·e^s: ½ s/(a − b) = 1/(2√(ab)) · (s/2)/sinh(s/2).
  for (double b : {0.5, 1.0, 3.0})
    for (double s : {0.0, 1e-16, 1e-12, 1e-8, 1e-4, 1e-1, -1e-1}) {
      const double a = b * std::exp(s), ls = std::log(a / b);
      const double exact = 0.5 / std::sqrt(a * b) * (ls == 0 ? 1 : ls / 2 / std::sinh(ls / 2));
      EXPECT_NEAR(half_log_difference(a, b), exact, 1e-15 / b) << "s = " << s;
    }
}

/// S(E) of a step from the Kirchhoff stress tau0 at εᵉ(t) = A tau0, through `law`.
template <class Law>
Voigt step_stress(const Voigt& tau0, const Voigt& E, double j_t, Law&& law) {
  HenckyStep h;
  h.start(steel.compliance() * tau0);
  const Voigt d = h.increment(E);
  return h.second_piola(law(d), j_t);
}

TEST(HenckyStrain, TangentMatchesFiniteDifferencesElastic) {
  std::mt19937 g(3);
  const double j_t = 1.002;
  for (int n = 0; n < 20; ++n) {
    const Voigt tau0 = random_voigt(g, 3e8), E = random_voigt(g, 0.05);
    auto law = [&](const Voigt& d) { return Voigt(tau0 + steel.stiffness() * d); };
    HenckyStep h;
    h.start(steel.compliance() * tau0);
    h.increment(E);
    const Voigt S = step_stress(tau0, E, j_t, law);
    const Mat6 c = h.tangent(S, steel.stiffness(), j_t);
    const Mat6 fd = central_differences(
        [&](const Voigt& e) { return step_stress(tau0, e, j_t, law); }, E, 1e-6);
    EXPECT_LT((c - fd).norm(), 1e-6 * fd.norm()) << "sample " << n;
  }
}

TEST(HenckyStrain, TangentMatchesFiniteDifferencesOnTheRadialReturn) {
  const Hardening hard(linear_spec(2.5e8, 1e9), constant(steel.E), constant(steel.nu));
  const StepCurve curve(hard, 20, 3 * steel.shear_modulus(), 0.01, true);
  std::mt19937 g(5);
  const double j_t = 0.999;
  int plastic = 0;
  for (int n = 0; n < 20; ++n) {
    Voigt tau0 = random_voigt(g, 1e8);
    tau0 *= 0.9 * curve.yield_now / von_mises(tau0);
    const Voigt E = random_voigt(g, 0.02);
    auto law = [&](const Voigt& d) { return radial_return(steel, curve, tau0, d).sigma; };
    HenckyStep h;
    h.start(steel.compliance() * tau0);
    const ReturnMapping r = radial_return(steel, curve, tau0, h.increment(E));
    plastic += r.plastic;
    const Voigt S = h.second_piola(r.sigma, j_t);
    const Mat6 c = h.tangent(S, r.tangent.matrix(steel), j_t);
    const Mat6 fd = central_differences(
        [&](const Voigt& e) { return step_stress(tau0, e, j_t, law); }, E, 1e-7);
    EXPECT_LT((c - fd).norm(), 1e-5 * fd.norm()) << "sample " << n;
  }
  EXPECT_GT(plastic, 15);  // the check is on the return, not only on the elastic trial
}

TEST(HenckyStrain, ARigidRotationMakesNoStrain) {
  // U = I for any rotation: the increment is zero, S = τ(t)/J(t) in the frame of x.
  std::mt19937 g(11);
  const Voigt tau0 = random_voigt(g, 2e8);
  HenckyStep h;
  h.start(steel.compliance() * tau0);
  const Voigt d = h.increment(Voigt::Zero());
  EXPECT_LT(d.norm(), 1e-14);  // exp and ln at 1 + 2εᵉ: round-off of 1
  EXPECT_LT((h.second_piola(tau0, 1.5) - tau0 / 1.5).norm(), 1e-15 * tau0.norm());
}

TEST(HenckyStrain, CoaxialStretchesAddTheirLogarithms) {
  // Principal axes fixed: ln λ1 + ln λ2 = ln(λ1 λ2), whatever the elastic strain at the start.
  const Vec3 l1(1.02, 0.99, 1.1), l2(0.97, 1.05, 1.2);
  Voigt eps_t = Voigt::Zero(), E = Voigt::Zero();
  for (int i = 0; i < 3; ++i) eps_t[i] = std::log(l1[i]), E[i] = 0.5 * (l2[i] * l2[i] - 1);
  HenckyStep h;
  h.start(eps_t);
  const Voigt d = h.increment(E);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(d[i], std::log(l2[i]), 1e-15);
  for (int i = 3; i < 6; ++i) EXPECT_EQ(d[i], 0.0);
}

TEST(HenckyStrain, UniaxialReturnInOneStepIsThatOfManySteps) {
  // A uniaxial Kirchhoff stress path with linear hardening, the lateral stretch free: the
  // total logarithmic strain 0.03 in 1 and in 100 equal increments of the axial stretch (each
  // step's lateral stretch from the converged state of a uniaxial stress, found by a scalar
  // Newton iteration on τ_xx = τ_yy = 0) ends at the same stress.
  const Hardening hard(linear_spec(2.5e8, 2e9), constant(steel.E), constant(steel.nu));
  auto run = [&](int steps) {
    Voigt tau = Voigt::Zero();
    double eps_p = 0;
    for (int s = 0; s < steps; ++s) {
      const StepCurve curve(hard, 20, 3 * steel.shear_modulus(), eps_p, true);
      const double lz = std::exp(0.03 / steps);
      double lx = 1, slope = 0;
      ReturnMapping r;
      auto stress_xx = [&](double x) {
        Voigt E = Voigt::Zero();
        E << 0.5 * (x * x - 1), 0.5 * (x * x - 1), 0.5 * (lz * lz - 1), 0, 0, 0;
        HenckyStep h;
        h.start(steel.compliance() * tau);
        r = radial_return(steel, curve, tau, h.increment(E));
        return r.sigma[0];
      };
      for (int it = 0; it < 20; ++it) {
        const double f = stress_xx(lx);
        if (std::abs(f) < 1e-4) break;
        slope = (stress_xx(lx * (1 + 1e-7)) - f) / (lx * 1e-7);
        lx -= f / slope;
      }
      EXPECT_LT(std::abs(stress_xx(lx)), 1e-3);  // and r is that of lx
      tau = r.sigma;
      eps_p += r.d_lambda;
    }
    return tau[2];
  };
  const double one = run(1), many = run(100);
  EXPECT_NEAR(one, many, 1e-9 * many);
  // τ = σ_y + H ε^p with ε^p = 0.03 − τ/E: τ = (σ_y + 0.03 H)/(1 + H/E).
  EXPECT_NEAR(one, (2.5e8 + 0.03 * 2e9) / (1 + 2e9 / steel.E), 1e-9 * one);
}

}  // namespace
}  // namespace hencky
