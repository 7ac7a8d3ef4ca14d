// Linear kinematic hardening (Prager) at one point: the consistent tangent against finite
// differences, and a uniaxial stress cycle against its closed form (the Bauschinger effect).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <random>

#include "material/kinematic.hpp"
#include "point_support.hpp"

namespace hencky {
namespace {

using namespace point_support;

TEST(KinematicHardening, TangentMatchesFiniteDifferences) {
  const Hardening h(linear_spec(2.5e8, 1e9), constant(steel.E), constant(steel.nu));
  const double three_g = 3 * steel.shear_modulus(), h_kin = 4e9;
  std::mt19937 g(7);
  std::uniform_real_distribution<double> d(-1, 1);
  for (int n = 0; n < 10; ++n) {
    Voigt alpha0, s0, x;
    for (int i = 0; i < 6; ++i) alpha0[i] = 3e7 * d(g), s0[i] = 1e8 * d(g), x[i] = 3e-3 * d(g);
    const double tr = (alpha0[0] + alpha0[1] + alpha0[2]) / 3;  // α is deviatoric
    for (int i = 0; i < 3; ++i) alpha0[i] -= tr;
    const double eps_p0 = 0.005;
    const StepCurve curve(h, 20, three_g, eps_p0, true);
    s0 = alpha0 + 0.9 * curve.yield_now / von_mises(s0) * s0;  // inside, near the surface
    const KinematicReturn r = kinematic_return(steel, curve, h_kin, s0, alpha0, x);
    ASSERT_TRUE(r.mapping.plastic);
    // On the moved surface, α deviatoric.
    EXPECT_NEAR(von_mises(r.mapping.sigma - r.alpha),
                h.plastic(eps_p0 + r.mapping.d_lambda, 20).value, 1e-9 * curve.yield_now);
    EXPECT_NEAR(r.alpha[0] + r.alpha[1] + r.alpha[2], 0.0, 1e-9 * r.alpha.norm());
    const Mat6 c = r.mapping.tangent.matrix(steel);
    const Mat6 fd = central_differences(
        [&](const Voigt& y) {
          return kinematic_return(steel, curve, h_kin, s0, alpha0, y).mapping.sigma;
        },
        x);
    EXPECT_LE((c - fd).norm(), 1e-5 * c.norm());
  }
}

/// Armstrong–Frederick with γ = 0 is Prager's rule: the same stress, back stress and tangent
/// as kinematic_return with H_k = ΣC_i, to round-off; with γ > 0 (two back stresses) the
/// point ends on the moved surface, each α_i is its backward-Euler update, and the tangent is
/// the finite differences' but for the nonsymmetric part the header names, computed here.
TEST(KinematicHardening, ArmstrongFrederickReturn) {
  const Hardening h(linear_spec(2.5e8, 1e9), constant(steel.E), constant(steel.nu));
  const double g2 = 2 * steel.shear_modulus(), three_g = 1.5 * g2;
  std::mt19937 g(11);
  std::uniform_real_distribution<double> d(-1, 1);
  auto deviatoric = [](Voigt a) {
    const double tr = (a[0] + a[1] + a[2]) / 3;
    for (int i = 0; i < 3; ++i) a[i] -= tr;
    return a;
  };
  int plastic = 0;
  for (int n = 0; n < 10; ++n) {
    std::array<Voigt, 2> a0;
    Voigt s0, x;
    for (int i = 0; i < 6; ++i)
      a0[0][i] = 3e7 * d(g), a0[1][i] = 2e7 * d(g), s0[i] = 1e8 * d(g), x[i] = 3e-3 * d(g);
    a0[0] = deviatoric(a0[0]);
    a0[1] = deviatoric(a0[1]);
    const StepCurve curve(h, 20, three_g, 0.005, true);
    s0 = a0[0] + a0[1] + 0.9 * curve.yield_now / von_mises(s0) * s0;
    // γ = 0: Prager's return of modulus C1 + C2.
    const std::array<BackStressLaw, 2> linear = {BackStressLaw{3e9, 0}, BackStressLaw{1e9, 0}};
    std::array<Voigt, 2> a1;
    const ReturnMapping r0 = armstrong_frederick_return(steel, curve, linear, s0, a0, x, a1);
    const KinematicReturn p = kinematic_return(steel, curve, 4e9, s0, Voigt(a0[0] + a0[1]), x);
    EXPECT_EQ(r0.plastic, p.mapping.plastic);
    if (!p.mapping.plastic) continue;  // an increment that unloads: elastic in both
    ++plastic;
    EXPECT_LE((r0.sigma - p.mapping.sigma).norm(), 1e-9 * p.mapping.sigma.norm());
    EXPECT_LE((a1[0] + a1[1] - p.alpha).norm(), 1e-9 * p.alpha.norm());
    EXPECT_LE((r0.tangent.matrix(steel) - p.mapping.tangent.matrix(steel)).norm(),
              1e-9 * p.mapping.tangent.matrix(steel).norm());
    // γ > 0.
    const std::array<BackStressLaw, 2> af = {BackStressLaw{3e10, 150}, BackStressLaw{5e9, 20}};
    const ReturnMapping r = armstrong_frederick_return(steel, curve, af, s0, a0, x, a1);
    ASSERT_TRUE(r.plastic);
    const double dl = r.d_lambda;
    EXPECT_NEAR(von_mises(Voigt(r.sigma - a1[0] - a1[1])), h.plastic(0.005 + dl, 20).value,
                1e-9 * curve.yield_now);
    const Voigt nd = 1.5 * deviatoric(Voigt(r.sigma - a1[0] - a1[1])) /
                     von_mises(Voigt(r.sigma - a1[0] - a1[1]));  // N, along ξ
    for (int i = 0; i < 2; ++i)
      EXPECT_LE((a1[i] * (1 + af[i].gamma * dl) - a0[i] - 2.0 / 3.0 * af[i].c * dl * nd).norm(),
                1e-9 * a0[i].norm());
    // The nonsymmetric part: −(2GΔλ·3/(2q*))·(P a')⊗N, P = I − (2/3)N⊗N, a' = Σγβ²α(t),
    // and the tangent's h, as the header writes them.
    Voigt xi = deviatoric(Voigt(s0 + steel.stiffness() * x)), ap = Voigt::Zero();
    double c_b2 = 0;
    for (int i = 0; i < 2; ++i) {
      const double b = 1 / (1 + af[i].gamma * dl);
      xi -= b * a0[i];
      ap += af[i].gamma * b * b * a0[i];
      c_b2 += af[i].c * b * b;
    }
    const double q = von_mises(xi);
    const Voigt nn = 1.5 * xi / q;
    auto contract = [](const Voigt& u, const Voigt& v) {
      return u[0] * v[0] + u[1] * v[1] + u[2] * v[2] +
             2 * (u[3] * v[3] + u[4] * v[4] + u[5] * v[5]);
    };
    const double hh = three_g + c_b2 + h.plastic(0.005 + dl, 20).slope - contract(nn, ap);
    const Voigt pa = ap - 2.0 / 3.0 * contract(nn, ap) * nn;
    const Mat6 nonsym = -(g2 * dl * 1.5 / q) * (g2 / hh) * pa * nn.transpose();
    const Mat6 fd = central_differences(
        [&](const Voigt& y) {
          std::array<Voigt, 2> tmp;
          return armstrong_frederick_return(steel, curve, af, s0, a0, y, tmp).sigma;
        },
        x);
    const Mat6 c = r.tangent.matrix(steel) + nonsym;
    EXPECT_LE((c - fd).norm(), 1e-5 * c.norm()) << "n = " << n;
  }
  EXPECT_GE(plastic, 5);  // the draws load plastically, mostly
}

/// A point driven along uniaxial stress: the axial strain prescribed, the lateral strains
/// iterated with the consistent tangent until σ22 = σ33 = 0.
struct UniaxialBar {
  const Hardening& h;
  double h_kin;
  Voigt sigma = Voigt::Zero(), alpha = Voigt::Zero(), eps = Voigt::Zero();
  double eps_p = 0;

  /// To axial strain e11; returns σ11.
  double to(double e11) {
    Voigt x = Voigt::Zero();
    x[0] = e11 - eps[0];
    x[1] = x[2] = -0.3 * x[0];
    const StepCurve curve(h, 20, 3 * steel.shear_modulus(), eps_p, true);
    KinematicReturn r;
    for (int it = 0; it < 50; ++it) {
      r = kinematic_return(steel, curve, h_kin, sigma, alpha, x);
      const Mat6 c = r.mapping.tangent.matrix(steel);
      Eigen::Matrix2d j;
      j << c(1, 1), c(1, 2), c(2, 1), c(2, 2);
      const Eigen::Vector2d f(r.mapping.sigma[1], r.mapping.sigma[2]);
      if (f.norm() < 1e-6) break;
      const Eigen::Vector2d dx = j.partialPivLu().solve(-f);
      x[1] += dx[0];
      x[2] += dx[1];
    }
    sigma = r.mapping.sigma;
    alpha = r.alpha;
    eps += x;
    eps_p += r.mapping.d_lambda;
    return sigma[0];
  }
};

TEST(KinematicHardening, UniaxialCycleShowsTheBauschingerEffect) {
  // Perfectly plastic isotropic part: the elastic range stays 2σ_y and moves with α.
  const double E = steel.E, sy = 2.5e8, hk = 2e10;
  const Hardening h(linear_spec(sy, 0.0), constant(E), constant(steel.nu));
  UniaxialBar bar{h, hk};
  // Loading to ε = 0.01: σ = σ_y + H_k ε_p with ε = σ/E + ε_p, so
  // σ = (σ_y + H_k ε)/(1 + H_k/E) (the tangent modulus E H_k/(E + H_k)).
  double s = 0;
  for (int i = 1; i <= 20; ++i) s = bar.to(0.01 * i / 20);
  const double s_peak = (sy + hk * 0.01) / (1 + hk / E);
  EXPECT_NEAR(s, s_peak, 1e-8 * s_peak);
  const double ep = 0.01 - s_peak / E;  // the plastic strain reached
  EXPECT_NEAR(bar.eps_p, ep, 1e-9);
  // The equivalent back stress (3/2)·α11 is H_k ε_p.
  EXPECT_NEAR(1.5 * bar.alpha[0], hk * ep, 1e-8 * hk * ep);
  // Unloading: elastic down to the reverse yield stress H_k ε_p − σ_y, 2σ_y below the peak.
  const double reverse = hk * ep - sy;
  const double e_reverse = 0.01 - (s_peak - reverse) / E;  // where it is reached
  for (int i = 1; i <= 10; ++i) {
    const double e = 0.01 - (0.01 - e_reverse) * (0.999 * i / 10);
    const double si = bar.to(e);
    EXPECT_NEAR(si, s_peak - E * (0.01 - e), 1e-8 * s_peak) << "still elastic at " << e;
  }
  EXPECT_DOUBLE_EQ(bar.eps_p, ep);
  // Past it, reverse flow: σ = H_k ε_p' − σ_y on the compression branch, with
  // ε = σ/E + ε_p' (ε_p' the net plastic strain).
  for (int i = 1; i <= 10; ++i) s = bar.to(e_reverse - 0.004 * i / 10);
  const double e_end = e_reverse - 0.004;
  const double s_end = (hk * e_end - sy) / (1 + hk / E);
  EXPECT_NEAR(s, s_end, 1e-8 * std::abs(s_end));
  EXPECT_NEAR(s_peak - reverse, 2 * sy, 1e-6 * sy);  // the elastic range
}

TEST(KinematicHardening, WithoutKinematicModulusItIsTheIsotropicReturnToTheLastBit) {
  const Hardening h(linear_spec(2.5e8, 3e9), constant(steel.E), constant(steel.nu));
  const StepCurve curve(h, 20, 3 * steel.shear_modulus(), 0.002, true);
  Voigt s0, x;
  s0 << 1e8, -2e7, 3e7, 4e7, -1e7, 2e7;
  x << 2e-3, -1e-3, 5e-4, 1e-3, 2e-4, -3e-4;
  const ReturnMapping a = radial_return(steel, curve, s0, x);
  const KinematicReturn b = kinematic_return(steel, curve, 0.0, s0, Voigt::Zero(), x);
  ASSERT_TRUE(a.plastic);
  EXPECT_EQ(a.sigma, b.mapping.sigma);
  EXPECT_EQ(a.d_lambda, b.mapping.d_lambda);
  EXPECT_EQ(a.tangent.coef, b.mapping.tangent.coef);
  EXPECT_EQ(a.tangent.v, b.mapping.tangent.v);
}

}  // namespace
}  // namespace hencky
