// The point level of plasticity: D̃(β*) and its identities (2.9)-(2.18), the radial return and
// its consistent tangent against finite differences, and every scheme's point law on a
// uniaxial stress path against the curve (which it must reproduce exactly).
#include <gtest/gtest.h>

#include <random>

#include "material/plastic_point.hpp"
#include "point_support.hpp"
#include "solve/schemes.hpp"

namespace hencky {
namespace {

using namespace point_support;
const IsotropicLaw isotropic;

/// ε̃ of a strain vector (engineering shears), (1.18) with c = 4/9.
double strain_intensity(const Voigt& e) {
  Voigt r = e;
  for (int i = 3; i < 6; ++i) r[i] *= 0.5;  // R of (1.19)
  const Voigt mr = m_times(r);
  // (Rε)ᵀ M (Rε) with M applied to the tensor components: m_times doubles shears, undo it.
  double s = 0;
  for (int i = 0; i < 3; ++i) s += r[i] * mr[i];
  for (int i = 3; i < 6; ++i) s += r[i] * mr[i];
  return std::sqrt(4.0 / 9.0 * s);
}

TEST(PlasticPoint, FlowDirectionHasUnitIntensityAndGivesVonMises) {
  std::mt19937 g(1);
  for (int k = 0; k < 20; ++k) {
    const Voigt s = random_voigt(g, 1e8);
    const Voigt z = flow_direction(s);
    EXPECT_NEAR(z.dot(s), von_mises(s), 1e-9 * von_mises(s));  // Zᵀσ = σ̃
    EXPECT_NEAR(strain_intensity(z), 1.0, 1e-12);               // ε̃(Z·λ) = λ
    EXPECT_NEAR(z[0] + z[1] + z[2], 0.0, 1e-12);                 // deviatoric
    EXPECT_NEAR(z.dot(steel.stiffness() * z), 3 * steel.shear_modulus(),
                1e-9 * steel.shear_modulus());  // ZᵀDZ = 3G
  }
}

TEST(PlasticPoint, DTildeIdentities) {
  std::mt19937 g(2);
  const double three_g = 3 * steel.shear_modulus();
  const Mat6 d = steel.stiffness(), I = Mat6::Identity();
  for (double tan_beta : {0.0, 0.01 * three_g, 0.3 * three_g, 0.999 * three_g, -0.2 * three_g}) {
    const Voigt z = flow_direction(random_voigt(g, 1e8));
    const Mat6 y = y_tilde(steel, z, tan_beta);
    const Mat6 dt = d_tilde(steel, z, tan_beta).matrix(steel);
    EXPECT_LE((dt - d * (I - y)).norm(), 1e-12 * d.norm()) << tan_beta;  // (2.9)
    EXPECT_LE((dt - dt.transpose()).norm(), 1e-12 * d.norm());
    const Voigt de_ep = random_voigt(g, 1e-3);
    const Voigt de_e = (I - y) * de_ep, de_p = y * de_ep;  // (2.14), (2.15)
    EXPECT_LE(((I - y) * de_p - y * de_e).norm(), 1e-12 * de_ep.norm());  // (2.16)
    // (2.17): the plastic part is along Z; (2.18): its intensity is (1 − tanβ*/tanβ^e) times
    // the projected e+p increment ZᵀDΔε/3G; (2.7): Δσ̃ = tanβ*·that.
    const double proj = z.dot(d * de_ep) / three_g;
    const double lambda = (1 - tan_beta / three_g) * proj;
    EXPECT_LE((de_p - lambda * z).norm(), 1e-10 * de_ep.norm());
    EXPECT_NEAR(z.dot(dt * de_ep), tan_beta * proj, 1e-9 * three_g * std::abs(proj) + 1e-6);
    // Tangent::times agrees with the matrix
    EXPECT_LE((d_tilde(steel, z, tan_beta).times(steel, de_ep) - dt * de_ep).norm(),
              1e-12 * (dt * de_ep).norm());
  }
  // (2.13): β* = β^e gives D; (2.11): E* limits.
  const Voigt z = flow_direction(random_voigt(g, 1e8));
  EXPECT_EQ((d_tilde(steel, z, three_g).matrix(steel) - d).norm(), 0.0);
  EXPECT_EQ(e_star(0.0, three_g), 0.0);
  EXPECT_TRUE(std::isinf(e_star(three_g, three_g)));
  // Perfect plasticity (tanβ* = 0): no stress increment along Z at all.
  EXPECT_NEAR((z.transpose() * d_tilde(steel, z, 0.0).matrix(steel)).norm(), 0.0,
              1e-9 * d.norm());
}

TEST(PlasticPoint, RadialReturnTangentMatchesFiniteDifferences) {
  const Hardening h(linear_spec(2.5e8, 3e9), constant(steel.E), constant(steel.nu));
  const double three_g = 3 * steel.shear_modulus();
  std::mt19937 g(3);
  for (double eps_p0 : {0.0, 0.01}) {
    for (bool elastic_unloading : {true, false}) {
      const StepCurve curve(h, 20, three_g, eps_p0, elastic_unloading);
      for (int k = 0; k < 10; ++k) {
        Voigt s0 = random_voigt(g, 1e8);
        s0 *= 0.9 * curve.yield_now / von_mises(s0);  // inside, near the surface
        const Voigt x = random_voigt(g, 3e-3);
        const ReturnMapping r = radial_return(steel, curve, s0, x);
        ASSERT_TRUE(r.plastic);
        EXPECT_NEAR(von_mises(r.sigma), h.plastic(eps_p0 + r.d_lambda, 20).value,
                    1e-10 * von_mises(r.sigma));
        const Mat6 c = r.tangent.matrix(steel);
        const Mat6 fd = central_differences(
            [&](const Voigt& y) { return radial_return(steel, curve, s0, y).sigma; }, x);
        EXPECT_LE((c - fd).norm(), 1e-5 * c.norm()) << "eps_p0 " << eps_p0;
      }
    }
  }
}

/// Drives one point along uniaxial stress with scheme `s`: the axial strain is prescribed, the
/// lateral strains are iterated (Newton on the point with a finite-difference Jacobian, standing
/// in for the global solve) until σ22 = σ33 = 0 and the scheme's parameters are stationary.
struct UniaxialPath {
  std::unique_ptr<Scheme> s;
  const Hardening& h;
  Voigt sigma = Voigt::Zero();
  Voigt eps_p = Voigt::Zero();
  double eps_p_eq = 0;
  bool flowing = false;

  void step(double d_axial) { ASSERT_NO_FATAL_FAILURE(run(d_axial)); }
  void run(double d_axial) {
    const double three_g = 3 * steel.shear_modulus();
    PointIteration it;
    const PointStep ps =
        s->begin_point_step(steel, isotropic, h, 20, true, sigma, eps_p_eq, flowing, it);
    Voigt x = Voigt::Zero();
    x[0] = d_axial;
    x[1] = x[2] = -steel.nu * d_axial;
    PointUpdate u;
    for (int k = 0; k < 400; ++k) {
      PointIteration probe = it;
      u = s->evaluate(steel, ps, it, sigma, x, {});
      if (!u.undefined) it = u.next;
      // lateral equilibrium: σ22 = σ33 = 0 by a secant-free 2x2 Newton on the current law
      Eigen::Matrix2d J;
      for (int j = 0; j < 2; ++j) {
        PointIteration tmp = probe;
        Voigt xp = x;
        xp[1 + j] += 1e-9;
        const Voigt sp = s->evaluate(steel, ps, tmp, sigma, xp, {}).sigma;
        J(0, j) = (sp[1] - u.sigma[1]) / 1e-9;
        J(1, j) = (sp[2] - u.sigma[2]) / 1e-9;
      }
      const Eigen::Vector2d r(u.sigma[1], u.sigma[2]);
      const Eigen::Vector2d dx = J.fullPivLu().solve(-r);
      x[1] += dx[0];
      x[2] += dx[1];
      if (r.norm() < 1e-6 && std::abs(u.defect_sigma) < 1e-6 &&
          std::abs(u.defect_eps) < 1e-15 && k > 2)
        break;
      ASSERT_LT(k, 399) << "the point iteration did not converge";
    }
    (void)three_g;
    sigma = u.sigma;
    eps_p += u.d_lambda * u.z;
    eps_p_eq += u.d_lambda;
    flowing = u.plastic;
  }
};

TEST(PlasticPoint, EverySchemeReproducesTheUniaxialCurveAndUnloadsWithSlopeE) {
  const double yield = 2.5e8, hard = 3e9;
  const Hardening h(linear_spec(yield, hard), constant(steel.E), constant(steel.nu));
  for (SchemeKind kind : {SchemeKind::newton, SchemeKind::variable_stiffness,
                          SchemeKind::initial_strain, SchemeKind::initial_strain_stiffness,
                          SchemeKind::initial_stress, SchemeKind::initial_stress_stiffness}) {
    {
      // The initial-strain iteration λ0 ← λ0 + ω(F(σ̃) − ε̃) has the factor 1 − ω(1 + 3G/H) at
      // first yield (elastic matrix, slope 1/H of F): it converges only for ω < 2H/(H + 3G),
      // about 0.026 here. The strain form of variable-stiffness (2.34) diverges at first yield
      // on this low-hardening curve (secant/tangent > 2); tested on the structure level.
      const bool initial_strain = kind == SchemeKind::initial_strain ||
                                  kind == SchemeKind::initial_strain_stiffness;
      SCOPED_TRACE(scheme_name(kind));
      UniaxialPath path{make_scheme(kind, CurveForm::stress, initial_strain ? 0.02 : 1.0), h};
      double eps = 0;
      // load to 5 yield strains in 10 steps
      const double de = 5 * yield / steel.E / 10;
      for (int k = 0; k < 10; ++k) {
        path.step(de);
        eps += de;
        const double s = path.sigma[0];
        // on the curve: σ = σ_y + H·ε^p with ε^p = ε − σ/E once past yield
        if (eps > yield / steel.E) {
          const double ep = eps - s / steel.E;
          EXPECT_NEAR(s, yield + hard * ep, 1e-6 * yield) << "step " << k;
          EXPECT_NEAR(path.eps_p_eq, ep, 1e-9);
          EXPECT_NEAR(path.eps_p[0], ep, 1e-9);
          EXPECT_NEAR(path.eps_p[1], -0.5 * ep, 1e-9);  // isochoric flow
        } else {
          EXPECT_NEAR(s, steel.E * eps, 1e-6 * yield);
        }
      }
      // initial-strain-stiffness unloads with the plastic tangent as matrix: its initial-strain
      // iteration then contracts by 1 − ω·tanβ*_0/3G per iteration (0.9997 here), so only its
      // loading branch is checked at the point level (docs/schemes.md, "Limits").
      if (kind == SchemeKind::initial_strain_stiffness) continue;
      // unload by two yield strains: slope E, plastic strain unchanged
      const double s_top = path.sigma[0], ep_top = path.eps_p_eq;
      path.step(-2 * yield / steel.E);
      EXPECT_NEAR(path.sigma[0], s_top - 2 * yield, 1e-6 * yield);
      EXPECT_NEAR(path.eps_p_eq, ep_top, 1e-12);
      // reload past the top: back on the curve where it left it
      path.step(2 * yield / steel.E + de);
      const double ep = eps + de - path.sigma[0] / steel.E;
      EXPECT_NEAR(path.sigma[0], yield + hard * ep, 1e-6 * yield);
    }
  }
}

/// D̃ with θ across Z (variable-stiffness's matrix): along Z the secant tan β*, across Z in the
/// deviator 2Gθ, the volume untouched; θ = 1 is D̃ itself.
TEST(PlasticPoint, DTildeScaledAcrossZ) {
  std::mt19937 g(5);
  const double three_g = 3 * steel.shear_modulus(), two_g = 2 * steel.shear_modulus();
  for (double theta : {1.0, 0.6, 0.05}) {
    for (double tan_beta : {0.0, 0.01 * three_g, 0.5 * three_g}) {
      const Voigt z = flow_direction(random_voigt(g, 1e8));
      const Tangent t = d_tilde(steel, z, tan_beta, theta);
      const Mat6 c = t.matrix(steel);
      EXPECT_LE((c - c.transpose()).norm(), 1e-12 * c.norm());
      const Voigt x = random_voigt(g, 1e-3);
      const double proj = z.dot(steel.stiffness() * x) / three_g;  // ZᵀDx/3G
      EXPECT_NEAR(z.dot(c * x), tan_beta * proj, 1e-9 * three_g * std::abs(proj));
      // a deviatoric strain across Z (engineering shears: its stress is 2G times it, halved
      // in the shear rows), made orthogonal to Z in the energy product
      Voigt e = random_voigt(g, 1e-3);
      const double tr = (e[0] + e[1] + e[2]) / 3;
      for (int i = 0; i < 3; ++i) e[i] -= tr;
      e -= (z.dot(steel.stiffness() * e) / z.dot(steel.stiffness() * z)) * z;
      EXPECT_LE((c * e - theta * (steel.stiffness() * e)).norm(), 1e-10 * two_g * e.norm());
      // the volume: a mean strain gives the bulk modulus' stress
      Voigt v = Voigt::Zero();
      v[0] = v[1] = v[2] = 1e-3;
      EXPECT_LE((c * v - steel.stiffness() * v).norm(), 1e-10 * (steel.stiffness() * v).norm());
      EXPECT_LE((t.times(steel, x) - c * x).norm(), 1e-12 * (c * x).norm());
    }
  }
  const Voigt z = flow_direction(random_voigt(g, 1e8));
  const double tb = 0.1 * three_g;
  EXPECT_EQ((d_tilde(steel, z, tb, 1.0).matrix(steel) - d_tilde(steel, z, tb).matrix(steel)).norm(),
            0.0);
}

/// Every scheme sees an iterate along its trial direction and gives the radial return's stress
/// for an increment that turns the stress: a point that flowed along xy shear and whose stress
/// turns to yz shear while its xy component falls. With the step's Z(t) its xy component was
/// put on the curve and its von Mises stress left above it (1.27 times the yield stress here,
/// the initial strains' answer before they took the trial direction).
TEST(PlasticPoint, EverySchemeGivesTheRadialReturnOfATurningStress) {
  const double yield = 2.5e8, hard = 3e9;
  const Hardening h(linear_spec(yield, hard), constant(steel.E), constant(steel.nu));
  const double g = steel.shear_modulus(), tau = yield / std::sqrt(3.0);
  Voigt sigma0 = Voigt::Zero();
  sigma0[3] = tau;  // τ_xy on the yield surface
  Voigt x = Voigt::Zero();
  x[3] = -0.1 * tau / g;  // engineering shears: τ = G γ
  x[4] = 0.9 * tau / g;
  const StepCurve curve(h, 20, 3 * g, 0.0, true);
  const ReturnMapping rr = radial_return(steel, curve, sigma0, x);
  ASSERT_TRUE(rr.plastic);
  struct Variant {
    SchemeKind kind;
    CurveForm form;
  };
  for (const Variant v : {Variant{SchemeKind::variable_stiffness, CurveForm::stress},
                          Variant{SchemeKind::variable_stiffness, CurveForm::strain},
                          Variant{SchemeKind::initial_stress, CurveForm::stress},
                          Variant{SchemeKind::initial_stress_stiffness, CurveForm::stress},
                          Variant{SchemeKind::initial_strain, CurveForm::strain},
                          Variant{SchemeKind::initial_strain_stiffness, CurveForm::strain}}) {
    const auto s = make_scheme(v.kind, v.form, 0.0);  // relaxation: auto
    SCOPED_TRACE(std::string(s->name()) + (v.form == CurveForm::strain ? " (strain form)" : ""));
    PointIteration it;
    const PointStep ps = s->begin_point_step(steel, isotropic, h, 20, true, sigma0, 0.0, true, it);
    ASSERT_LT(ps.z.dot(Tangent{}.times(steel, x)), 0);                // unloading along Z(t)
    ASSERT_GT(von_mises(sigma0 + Tangent{}.times(steel, x)), yield);  // outside the surface
    PointUpdate u = s->evaluate(steel, ps, it, sigma0, x, {});
    // the strain held: the point's own iteration (the stress forms land at once)
    for (int k = 0; k < 100 && std::abs(u.defect_sigma) + std::abs(u.defect_eps) > 0; ++k)
      u = s->evaluate(steel, ps, u.next, sigma0, x, {});
    EXPECT_TRUE(u.plastic);
    EXPECT_LE((u.sigma - rr.sigma).norm(), 1e-9 * yield);
    EXPECT_NEAR(u.d_lambda, rr.d_lambda, 1e-9 * rr.d_lambda);
    EXPECT_NEAR(von_mises(u.sigma), h.plastic(u.d_lambda, 20).value, 1e-9 * yield);
  }
}

/// The initial-strain schemes' held plastic set: a point held plastic whose iterate falls
/// below the yield stress stays on the plastic branch (continued: its plastic strain
/// decreases) and says its hold is broken; a point held elastic above the yield stress stays
/// elastic and says so too; free, each takes the other status.
TEST(PlasticPoint, InitialStrainHeldPointsKeepTheirBranch) {
  const double yield = 2.5e8, hard = 3e9;
  const Hardening h(linear_spec(yield, hard), constant(steel.E), constant(steel.nu));
  const double three_g = 3 * steel.shear_modulus(), tau = yield / std::sqrt(3.0);
  for (SchemeKind kind : {SchemeKind::initial_strain, SchemeKind::initial_strain_stiffness}) {
    SCOPED_TRACE(scheme_name(kind));
    const auto s = make_scheme(kind, CurveForm::strain, 0.0);  // relaxation: auto
    Voigt sigma0 = Voigt::Zero();
    sigma0[3] = 0.5 * tau;             // elastic at t
    for (double reach : {0.9, 1.2}) {  // the trial stress over the yield stress
      Voigt x = Voigt::Zero();
      x[3] = (reach - 0.5) * tau / steel.shear_modulus();
      for (int held : {0, 1, -1}) {
        PointIteration it;
        const PointStep ps =
            s->begin_point_step(steel, isotropic, h, 20, true, sigma0, 0.0, false, it);
        it.held = static_cast<signed char>(held);
        const PointUpdate u = s->evaluate(steel, ps, it, sigma0, x, {});
        const bool plastic = held == 0 ? reach > 1 : held > 0;
        EXPECT_EQ(u.plastic, plastic) << "reach " << reach << " held " << held;
        EXPECT_EQ(u.next.breaks_hold, held != 0 && plastic != (reach > 1))
            << "reach " << reach << " held " << held;
        if (held > 0 && reach < 1) {
          // λ0 = ω (σ̃ − σ_y)/H with ω = H/(3G + H): the plastic branch's defect, negative
          EXPECT_NEAR(u.z.dot(Tangent{}.times(steel, u.next.e0)) / three_g,
                      (reach - 1) * yield / (three_g + hard), 1e-12);
        }
      }
    }
  }
}

}  // namespace
}  // namespace hencky
