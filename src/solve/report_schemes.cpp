// The report's five schemes as it writes them (solver.formulation: report), beside hencky's
// (schemes.cpp, fixed_matrix_schemes.cpp), which add to them. Every point law here is one
// equation of the report:
//
//   (2.10) Z = Mσ(t)/σ̃(t), fixed over the step;
//   (2.33) variable stiffness, stress form: tan β*_{k+1} = (Φ(ε̃(t) + Δε̃_k) − σ̃(t))/Δε̃_k;
//   (2.34) variable stiffness, strain form: tan β*_{k+1} = Δσ̃_k/(F(σ̃(t) + Δσ̃_k) − ε̃(t));
//   (2.37), (2.40) initial strains: Δε^0_{k+1} = Δε^0_k + ω(F(σ̃(t) + Δσ̃_k) − (ε̃(t) + Δε̃_k))·Z;
//   (2.43), (2.46) initial stresses: Δσ^0_{k+1} = (D̃(β**_{k+1}) − D̃(β*))Δε_k, with
//                  tan β**_{k+1} = (Φ(ε̃(t) + Δε̃_k) − σ̃(t))/Δε̃_k;
//
// with the matrix D (schemes 2, 4), the start-of-step tangent D̃(β*_0) (3, 5) or the secant
// D̃(β*_k) (1), and the measures Δ^σ_k, Δ^ε_k written under each. The step loop solves them in
// residual form (schemes.hpp): the stress an iterate returns is the one of the parameters of the
// next solve, σ(t) + D̃(x_k − Δε^0_{k+1}) + Δσ^0_{k+1}, so that K_{k+1}(Δu_{k+1} − Δu_k) =
// F − F_int(σ_k) is the report's (2.29) for Δu_{k+1}.
//
// What the report leaves open, decided here (docs/schemes.md, "formulation: report"), and what
// tests/tools/report_schemes.py implements again from the report's equations:
// - Δε̃^{e+p}_k, the scalar increment of x = Δε_k − Δε^th, is ZᵀDx/3G: the one the matrix
//   D̃ works with (ZᵀD̃x = tan β*·ZᵀDx/3G, (2.7)); Δσ̃_k = ZᵀΔσ_k;
// - ε̃^{e+p}(t) is the state these increments advanced (State::eps_ep) where the point ended
//   the step before at the largest ε̃ it reached, else the strain of σ̃(t) on the step's curve,
//   F(σ̃(t)) (begin_point_step says why); σ̃(t) is the von Mises stress of σ(t);
// - a point whose stress at t is below 1e-12 of its yield stress has no direction Z(t): it
//   takes that of the iterate's trial stress σ(t) + Dx (FORMULATION.md: the current stress
//   estimate), and the `-stiffness` matrix is D there;
// - elastic unloading (the end of section 2): below the largest ε̃^{e+p} reached, the line of
//   slope 3G(t+Δt) through the curve's point there;
// - tan β*_0 is the curve's slope at ε̃(t): its loading slope where ε̃(t) is the largest reached
//   (the point stands on the curve's rising branch), else the line's 3G;
// - a secant over an increment below 1e-8 of the strain (or stress) is the curve's slope there,
//   its limit (the secant of a vanishing increment is 0/0);
// - ω of (2.37) is a number, 1 unless solver.relaxation gives one;
// - the measures are hencky's global RMS of the points' Δ^σ_k, Δ^ε_k (PointPass::measures),
//   without the points elastic in this iterate and the one before.
// No point law here takes the iterate's own direction, relaxes, switches forms or slopes, or
// holds a plastic set: where the report's map leaves a point off the curve, it stays off
// (report.largest_yield_excess says by how much).
#include <cmath>
#include <memory>

#include "core/invariant.hpp"
#include "solve/schemes.hpp"

namespace hencky {
namespace {

/// Below this fraction of the yield stress σ(t) gives no direction.
constexpr double no_direction = 1e-12;
/// Below this fraction of ε̃ (of σ̃) an increment has no secant: the slope is taken.
constexpr double no_secant = 1e-8;

/// The iterate x seen along the step's Z.
struct Along {
  Voigt z, dx;      ///< Z and Dx
  double q0 = 0;    ///< σ̃(t)
  double eps0 = 0;  ///< ε̃^{e+p}(t)
  double xt = 0;    ///< Δε̃^{e+p}_k = ZᵀDx/3G
};

class ReportScheme : public Scheme {
 public:
  ReportScheme(SchemeKind kind, MatrixPolicy policy, bool strain_form)
      : kind_(kind), policy_(policy), strain_form_(strain_form) {}
  SchemeKind kind() const override { return kind_; }
  MatrixPolicy matrix_policy() const override { return policy_; }
  bool uses_strain_form() const override { return strain_form_; }
  bool has_initial_evaluation() const override { return true; }

  PointStep begin_point_step(const ElasticConstants& k1, const PointLaw& law, const Hardening& h,
                             double T1, bool elastic_unloading, const PointAtT& at,
                             PointIteration& it) const override {
    PointStep ps;
    ps.law = &law;
    const double three_g = 3 * k1.shear_modulus();
    // The elastic line through the curve's point at the largest ε̃ reached meets σ̃ = 0 at
    // ε̃_max − Φ(ε̃_max)/3G: StepCurve's ε̃^p; its kink is put at ε̃_max itself, so that a point
    // that stands there takes the branch its flag says and not that of a rounding.
    ps.curve = StepCurve(h, T1, three_g, 0, elastic_unloading);
    if (elastic_unloading && at.eps_ep_max > ps.curve.eps_yield_now) {
      const double top = h.phi(at.eps_ep_max, T1, three_g).value;
      ps.curve = StepCurve(h, T1, three_g, std::max(0.0, at.eps_ep_max - top / three_g), true);
      ps.curve.yield_now = top;
      ps.curve.eps_yield_now = at.eps_ep_max;
    }
    const double q0 = von_mises(at.sigma);
    if (q0 > no_direction * ps.curve.yield_now) ps.z = flow_direction(at.sigma);  // (2.10)
    // ε̃^{e+p}(t): on the rising branch (the step before ended at the largest ε̃ reached) the
    // state the increments advanced; below it, the strain of σ̃(t) on the step's curve, F(σ̃(t)).
    // The increments are signed along Z(t), and σ̃(t) is not: where the stress passed through
    // zero in the step before, Z turned over and the advanced scalar had gone down the elastic
    // line past its foot, Φ(ε̃(t)) < 0 < σ̃(t), which (2.33)-(2.46) would read as a plastic
    // strain (q0 − Φ(ε̃(t)))/3G in the next step. F(σ̃(t)) is the scalar the report's curve
    // gives σ(t): an unloaded point restarts along its new Z from the foot of its line, as
    // isotropic hardening has it. (The same at a new temperature's curve and 3G.)
    ps.flowing = at.eps_ep >= at.eps_ep_max;
    ps.eps_ep = at.eps_ep;
    // A point not on its rising branch but at or above its yield stress (the report's map can
    // leave σ̃(t) above the curve where the stress turned) stands at the kink, ε̃_max: reading
    // F there would raise its hardening by the excess.
    if (!ps.flowing)
      ps.eps_ep = q0 < ps.curve.yield_now ? ps.curve.f(q0).value : ps.curve.eps_yield_now;
    // tan β*_0: the curve's slope at the step's start, Φ'(ε̃(t)) (2.33), (2.46); (2.34) and
    // (2.40) write it 1/F'(σ̃(t)), the same slope at the same point of the curve. On the rising
    // branch the loading side of a kink; a point without a direction (σ̃(t) = 0) is at the foot
    // of its elastic line: 3G.
    ps.tan0 = has_direction(ps) ? ps.curve.phi(ps.eps_ep, ps.flowing).slope : three_g;
    it = start_iteration(ps);
    return ps;
  }

  /// The report's curve at the largest ε̃^{e+p} reached: the top of the elastic line below it
  /// (with the report's elastic unloading), or the curve at ε̃^{e+p} itself without it.
  double yield_stress(const PointStep& ps, double, double eps_ep,
                      double eps_ep_max) const override {
    const StepCurve& c = ps.curve;
    if (!c.elastic_unloading) return c.phi(eps_ep).value;
    return eps_ep_max > c.eps_yield_now
               ? c.hardening->phi(eps_ep_max, c.temperature, c.three_g).value
               : c.yield_now;
  }

  PointUpdate evaluate_initial(const ElasticConstants& k1, const PointStep& ps,
                               const PointIteration& it, const Voigt& sigma0,
                               const Voigt& x) const override {
    const Along a = along(k1, ps, sigma0, x);
    const double t0 = start_matrix_slope(ps, it);
    PointUpdate u = stress_of(k1, ps, sigma0, a, (1 - t0 / ps.curve.three_g) * a.xt);
    u.tangent = d_tilde(k1, a.z, t0);
    u.next = it;
    return u;
  }

 protected:
  /// tan β* of the step's first matrix: D̃(β*_0) of variable stiffness and of the `-stiffness`
  /// schemes, D of the others (and where the point has no direction Z(t)).
  virtual double start_matrix_slope(const PointStep& ps, const PointIteration& it) const = 0;

  static bool has_direction(const PointStep& ps) { return ps.z.squaredNorm() > 0; }

  static Along along(const ElasticConstants& k1, const PointStep& ps, const Voigt& sigma0,
                     const Voigt& x) {
    Along a;
    a.dx = Tangent{}.times(k1, x);
    a.z = has_direction(ps) ? ps.z : flow_direction(sigma0 + a.dx);
    a.q0 = von_mises(sigma0);
    a.eps0 = ps.eps_ep;
    a.xt = a.z.dot(a.dx) / ps.curve.three_g;
    return a;
  }

  /// The secant of the stress form over the step, (Φ(ε̃ + Δε̃) − σ̃(t))/Δε̃: tan β* of (2.33) and
  /// tan β** of (2.43), (2.46); the slope at ε̃(t) for a vanishing increment.
  static double stress_secant(const PointStep& ps, const Along& a, double phi) {
    const double small = no_secant * std::max(std::abs(a.eps0), ps.curve.eps_yield_now);
    return std::abs(a.xt) > small ? (phi - a.q0) / a.xt : ps.curve.phi(a.eps0, ps.flowing).slope;
  }

  /// The iterate's stress σ(t) + D(x − Zλ) for the plastic multiplier λ along Z, and its state.
  static PointUpdate stress_of(const ElasticConstants& k1, const PointStep& ps,
                               const Voigt& sigma0, const Along& a, double lambda) {
    PointUpdate u;
    u.z = a.z;
    u.d_lambda = lambda;
    u.sigma = sigma0 + a.dx - lambda * Tangent{}.times(k1, a.z);
    u.eps_ep = a.eps0 + a.xt;
    // Counted as flowing above round-off (the stress keeps λ as it is).
    u.plastic = std::abs(lambda) > 1e-12 * std::max(std::abs(u.eps_ep), ps.curve.eps_yield_now);
    return u;
  }

  /// The memory of the next iteration (remember_iterate, with the initial strain's λ0).
  static void remember(PointUpdate& u, const PointIteration& it, const Along& a, double ds,
                       double tan_beta, double lambda0) {
    remember_iterate(u, it, a.xt, ds, tan_beta);
    u.next.lambda0 = lambda0;
  }

 private:
  SchemeKind kind_;
  MatrixPolicy policy_;
  bool strain_form_;
};

/// Scheme 1, (2.32)-(2.34): the secant D̃(β*_k), rebuilt every iteration.
class ReportVariableStiffness final : public ReportScheme {
 public:
  explicit ReportVariableStiffness(bool strain_form)
      : ReportScheme(SchemeKind::variable_stiffness, MatrixPolicy::per_iteration, strain_form) {}
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x, const LawState&) const override {
    const Along a = along(k1, ps, sigma0, x);
    const double ds = it.tan_beta * a.xt;  // Δσ̃_k of the solve with D̃(β*_k)
    double new_tan = it.tan_beta, defect_sigma = 0, defect_eps = 0;
    bool undefined = false;
    if (uses_strain_form()) {  // (2.34)
      const Hardening::Point fk = ps.curve.f(a.q0 + ds, ps.flowing);
      undefined = !std::isfinite(fk.value);
      if (!undefined) {
        defect_eps = fk.value - (a.eps0 + it.x_prev);
        defect_sigma = ds - it.ds_prev;
        const double den = fk.value - a.eps0;
        const double small = no_secant * std::max(std::abs(a.q0), ps.curve.yield_now);
        new_tan = std::abs(ds) > small && den != 0 ? ds / den : 1 / fk.slope;
      }
    } else {  // (2.33)
      const double phi = ps.curve.phi(a.eps0 + a.xt, ps.flowing).value;
      defect_sigma = phi - (a.q0 + ds);
      defect_eps = a.xt - it.x_prev;
      new_tan = stress_secant(ps, a, phi);
    }
    // σ_k = σ(t) + D̃(β*_{k+1})x: the multiplier (1 − tan β*/3G)Δε̃ along Z, (2.18).
    PointUpdate u = stress_of(k1, ps, sigma0, a, (1 - new_tan / ps.curve.three_g) * a.xt);
    u.undefined = undefined;
    u.negative_secant = new_tan < 0;
    u.defect_sigma = defect_sigma;
    u.defect_eps = defect_eps;
    u.tangent = d_tilde(k1, a.z, new_tan);
    remember(u, it, a, ds, new_tan, 0);
    return u;
  }

 protected:
  double initial_tan_beta(double tan0, double) const override { return tan0; }
  double start_matrix_slope(const PointStep&, const PointIteration& it) const override {
    return it.tan_beta;
  }
};

/// What the fixed-matrix schemes 2-5 share: the matrix D, or D̃(β*_0) with the start-of-step
/// tangent (the `-stiffness` variants), the same at every iteration of the step.
class ReportFixedMatrix : public ReportScheme {
 public:
  ReportFixedMatrix(SchemeKind kind, bool stiffness, bool strain_form)
      : ReportScheme(kind, stiffness ? MatrixPolicy::per_step : MatrixPolicy::elastic,
                     strain_form),
        stiffness_(stiffness) {}

 protected:
  /// tan β* of the matrix: tan β*_0 or 3G (β^e, (2.35), (2.41)).
  double matrix_slope(const PointStep& ps) const {
    return stiffness_ && has_direction(ps) ? ps.tan0 : ps.curve.three_g;
  }
  double start_matrix_slope(const PointStep& ps, const PointIteration&) const override {
    return matrix_slope(ps);
  }
  double initial_tan_beta(double tan0, double three_g) const override {
    return stiffness_ ? tan0 : three_g;
  }
  /// The matrix D̃(β*) of every iteration.
  Tangent matrix(const ElasticConstants& k1, const PointStep& ps, const Along& a) const {
    return d_tilde(k1, a.z, matrix_slope(ps));
  }

 private:
  bool stiffness_;
};

/// Schemes 2 and 3, (2.35)-(2.40): initial strains Δε^0 = Z·λ0 relaxed by ω, on the curve's
/// strain form.
class ReportInitialStrain final : public ReportFixedMatrix {
 public:
  ReportInitialStrain(bool stiffness, double omega)
      : ReportFixedMatrix(stiffness ? SchemeKind::initial_strain_stiffness
                                    : SchemeKind::initial_strain,
                          stiffness, true),
        omega_(omega) {}
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x, const LawState&) const override {
    const Along a = along(k1, ps, sigma0, x);
    const double tb = matrix_slope(ps), three_g = ps.curve.three_g;
    // Δσ_k = D̃(β*)(x − Zλ0_k): along Z, tan β*·(Δε̃_k − λ0_k) (ZᵀDZ = 3G).
    const double ds = tb * (a.xt - it.lambda0);
    const Hardening::Point fk = ps.curve.f(a.q0 + ds, ps.flowing);
    double lambda0 = it.lambda0, defect_eps = 0;
    if (std::isfinite(fk.value)) {
      defect_eps = fk.value - (a.eps0 + a.xt);
      lambda0 += omega_ * defect_eps;  // (2.37), (2.40)
    }
    // σ_k = σ(t) + D̃(β*)(x − Zλ0_{k+1}): D̃ adds (1 − tan β*/3G) of the rest along Z, (2.25).
    const double lambda = lambda0 + (1 - tb / three_g) * (a.xt - lambda0);
    PointUpdate u = stress_of(k1, ps, sigma0, a, lambda);
    u.undefined = !std::isfinite(fk.value);
    u.defect_eps = defect_eps;
    u.defect_sigma = ds - it.ds_prev;
    u.tangent = matrix(k1, ps, a);
    remember(u, it, a, ds, it.tan_beta, lambda0);
    return u;
  }

 private:
  double omega_;
};

/// Schemes 4 and 5, (2.41)-(2.46): initial stresses Δσ^0 = (D̃(β**) − D̃(β*))Δε, on the curve's
/// stress form.
class ReportInitialStress final : public ReportFixedMatrix {
 public:
  explicit ReportInitialStress(bool stiffness)
      : ReportFixedMatrix(stiffness ? SchemeKind::initial_stress_stiffness
                                    : SchemeKind::initial_stress,
                          stiffness, false) {}
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x, const LawState&) const override {
    const Along a = along(k1, ps, sigma0, x);
    const double tb = matrix_slope(ps);
    // Δσ_k = D̃(β*)x_k + Δσ^0_k, Δσ^0_k = (D̃(β**_k) − D̃(β*))x_{k−1}: along Z
    const double ds = tb * a.xt + (it.tan_beta - tb) * it.x_prev;
    const double phi = ps.curve.phi(a.eps0 + a.xt, ps.flowing).value;
    const double new_tan = stress_secant(ps, a, phi);  // tan β**_{k+1}
    // σ_k = σ(t) + D̃(β*)x_k + Δσ^0_{k+1} = σ(t) + D̃(β**_{k+1})x_k
    PointUpdate u = stress_of(k1, ps, sigma0, a, (1 - new_tan / ps.curve.three_g) * a.xt);
    u.defect_sigma = phi - (a.q0 + ds);
    u.defect_eps = a.xt - it.x_prev;
    u.tangent = matrix(k1, ps, a);
    remember(u, it, a, ds, new_tan, 0);
    return u;
  }
};

}  // namespace

std::unique_ptr<Scheme> make_report_scheme(SchemeKind kind, CurveForm form, double omega) {
  switch (kind) {
    case SchemeKind::variable_stiffness:
      return std::make_unique<ReportVariableStiffness>(form == CurveForm::strain);
    case SchemeKind::initial_strain:
    case SchemeKind::initial_strain_stiffness:
      return std::make_unique<ReportInitialStrain>(kind == SchemeKind::initial_strain_stiffness,
                                                   omega > 0 ? omega : 1.0);
    case SchemeKind::initial_stress:
    case SchemeKind::initial_stress_stiffness:
      return std::make_unique<ReportInitialStress>(kind == SchemeKind::initial_stress_stiffness);
    case SchemeKind::newton:
      break;
  }
  HENCKY_VERIFY(false, "newton is not one of the report's schemes");
}

}  // namespace hencky
