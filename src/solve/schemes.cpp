// The schemes' shared start of a step, newton and variable-stiffness (scheme 1), and the
// factory of all six; the fixed-matrix schemes are in fixed_matrix_schemes.cpp.
#include "solve/schemes.hpp"

#include <algorithm>
#include <cmath>

#include "core/invariant.hpp"
#include "solve/scheme_law.hpp"

namespace hencky {

PointStep Scheme::begin_point_step(const ElasticConstants& k1, const PointLaw& law,
                                   const Hardening& h, double T1, bool elastic_unloading,
                                   const PointAtT& at, PointIteration& it) const {
  const Voigt& sigma0 = at.sigma;
  const double eps_p0 = at.eps_p;
  const bool flowing = at.flowing;
  PointStep ps;
  ps.law = &law;
  const double three_g = 3 * k1.shear_modulus();
  ps.curve = StepCurve(h, T1, three_g, eps_p0, elastic_unloading);
  ps.flowing = flowing && von_mises(sigma0) > 0;
  ps.tan0 = three_g;  // a point elastic at t starts on the elastic line
  if (ps.flowing) {
    ps.z = flow_direction(sigma0);  // (2.10)
    // A point that flowed sits on its yield surface H(ε̃^p) up to round-off: σ̃(t) an ulp below
    // it is still on the curve, and its start slope is the curve's (loading side), not the
    // elastic 3G that Φ gives an ulp below. (When the temperature of t+Δt raises the yield
    // stress above σ̃(t) by more than round-off, the point is inside the elastic range: 3G.)
    double q0 = ps.z.dot(sigma0);
    if (q0 < ps.curve.yield_now && q0 >= ps.curve.yield_now * (1 - 1e-12)) q0 = ps.curve.yield_now;
    if (uses_strain_form()) {
      // tan β*_0 = 1 / F'(σ̃(t)), (2.34), (2.40); 0 where F is flat-ended (perfect plasticity).
      const double df = ps.curve.f(q0, true).slope;
      ps.tan0 = std::isfinite(df) && df > 0 ? 1 / df : 0.0;
    } else {
      // tan β*_0 = Φ'(ε̃(t)), (2.33), (2.46)
      ps.tan0 = ps.curve.phi(eps_p0 + q0 / three_g, true).slope;
    }
  }
  it = start_iteration(ps);
  return ps;
}

PointUpdate Scheme::evaluate_initial(const ElasticConstants&, const PointStep&,
                                     const PointIteration&, const Voigt&, const Voigt&) const {
  HENCKY_VERIFY(false, "evaluate_initial is the report's schemes' only");
}

double Scheme::yield_stress(const PointStep& ps, double eps_p, double, double) const {
  // A point that did not flow in the step keeps the yield stress of its step's curve: no
  // evaluation of the curve at most points of most iterates.
  if (eps_p == ps.curve.eps_p) return ps.curve.yield_now;
  return ps.curve.hardening->plastic(std::max(eps_p, 0.0), ps.curve.temperature).value;
}

void remember_iterate(PointUpdate& u, const PointIteration& it, double xt, double ds,
                      double tan_beta) {
  if (!u.plastic && !it.plastic_prev) u.defect_sigma = u.defect_eps = 0;
  u.next = it;
  u.next.x_prev = xt;
  u.next.ds_prev = ds;
  u.next.tan_beta = tan_beta;
  u.next.plastic_prev = u.plastic;
  ++u.next.k;
}

PointIteration Scheme::start_iteration(const PointStep& ps) const {
  PointIteration it;
  it.tan_beta = initial_tan_beta(ps.tan0, ps.curve.three_g);
  it.plastic_prev = false;
  it.tan_start = ps.tan0;
  return it;
}

namespace {

using namespace scheme_law;

/// The reference: the material's point law with its consistent tangent (for von Mises with the
/// isotropic curve, the radial return).
class Newton final : public Scheme {
 public:
  SchemeKind kind() const override { return SchemeKind::newton; }
  MatrixPolicy matrix_policy() const override { return MatrixPolicy::per_iteration; }
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x, const LawState& law) const override {
    const double three_g = ps.curve.three_g;
    const Voigt dx = Tangent{}.times(k1, x);  // D x
    PointUpdate u;
    const ReturnMapping rr = ps.law->update(k1, ps.curve, sigma0, x, law.at_t, law.now);
    const double q = von_mises(rr.sigma), q0 = rr.z.dot(sigma0);
    const double xt = rr.z.dot(dx) / three_g;
    u.sigma = rr.sigma;
    u.z = rr.z;
    u.d_lambda = rr.d_lambda;
    u.plastic = rr.plastic;
    u.tangent = rr.tangent;
    u.eps_ep = ps.curve.eps_p + rr.d_lambda + q / three_g;
    if (u.plastic || it.plastic_prev) {
      u.defect_sigma = (q - q0) - it.ds_prev;
      u.defect_eps = xt - it.x_prev;
    }
    u.next = it;
    u.next.ds_prev = q - q0;
    u.next.x_prev = xt;
    u.next.plastic_prev = u.plastic;
    ++u.next.k;
    return u;
  }
};

/// Scheme 1, (2.32)-(2.34): the secant matrix D̃(β*_k), rebuilt every iteration, on the
/// curve's stress form Φ (2.33) or its strain form F (2.34).
class VariableStiffness final : public Scheme {
 public:
  explicit VariableStiffness(bool strain_form) : strain_form_(strain_form) {}
  /// Above the curve: σ̃(t) beyond the yield stress by more than this, relative (a millionth:
  /// the strain it owes the curve is then below 1e-6 σ_y / H, far under a step's increment).
  static constexpr double above_curve_slack = 1e-6;
  SchemeKind kind() const override { return SchemeKind::variable_stiffness; }
  MatrixPolicy matrix_policy() const override { return MatrixPolicy::per_iteration; }
  bool uses_strain_form() const override { return strain_form_; }
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x,
                       const LawState& /*law*/) const override {
    const double three_g = ps.curve.three_g;
    const AlongZ a = along_z(k1, ps, sigma0, x);
    const bool right = ps.flowing;
    const double q_tr = a.q0 + three_g * a.xt;  // Zᵀ(σ(t) + Dx), Z the trial's direction
    PointUpdate u;
    double lambda = 0, new_tan = it.tan_beta;
    const double ds = it.tan_beta * a.xt;  // Δσ̃_k of the solve with D̃(β*_k)
    // The strain form, unless the point has turned to the stress form in this step (below),
    // or starts the step above the curve, where F(σ̃(t)) lies beyond ε̃(t): a yield stress that
    // falls with the temperature of t+Δt, or an answer at t left above the curve (when Z was
    // still Z(t), a point under an indenter ended its step there). Its answer along Z has a
    // negative secant (its stress falls back to the curve while its strain grows), which (2.34)
    // cannot reach from a positive one: the secant Δσ̃/(F(σ̃ + Δσ̃) − ε̃) only shrinks towards
    // zero (measured then, the ball indentation with curve_form: strain, t = 0.625 → 0.75:
    // secants of 6e3 Pa and falling by a fifth per iteration, the step cut back four times).
    // The stress form takes it, as for a negative secant below.
    const bool above_curve = ps.flowing && a.q0 > ps.curve.yield_now * (1 + above_curve_slack);
    const bool strain_now = strain_form_ && !it.stress_form && !above_curve;
    const auto fk = strain_now ? ps.curve.f(a.q0 + ds, right) : Hardening::Point{};
    // An iterate above the largest stress the curve reaches (the flat end of a table) has no
    // strain on the curve: the point takes the stress form as well (Φ is flat there).
    bool stress_form = !strain_now || !std::isfinite(fk.value);
    // A point that flowed and whose trial stress turned from Z(t) within the step: its secant
    // along Z(t), the memory's, can put the estimate σ̃(t) + tan β*·Δε̃ inside the yield
    // surface while the trial stress lies outside it, so (2.34) would take the iterate as
    // elastic with a stress outside the surface. The stress form's iterate does not depend on
    // the secant: the point takes it (both forms have the curve as their fixed point).
    stress_form =
        stress_form || (ps.flowing && a.q0 + ds < ps.curve.yield_now && q_tr > ps.curve.yield_now);
    bool defects_set = false;
    double change = 0;  // tan β*_{k+1} − tan β*_k of the strain form
    if (!stress_form) {  // (2.34)
      u.defect_eps = fk.value - (a.eps0 + it.x_prev);
      u.defect_sigma = ds - it.ds_prev;
      defects_set = true;
      const double den = fk.value - a.eps0;
      // As above: the secant Δσ̃/(F(σ̃ + Δσ̃) − ε̃) is noise for Δσ̃ at round-off level.
      new_tan = std::abs(ds) > 1e-8 * std::max(std::abs(a.q0), ps.curve.yield_now) && den != 0
                    ? ds / den
                    : 1 / fk.slope;
      lambda = (three_g - new_tan) / three_g * a.xt;
      // A point whose strain its surroundings hold (a restrained bar heated, a layer under a
      // prescribed displacement) multiplies the error of its secant by 1 − tan β*/tan β (the
      // secant over the curve's slope) per iteration: below −1 once the curve hardens less than
      // half its secant, and at first yield the secant then alternates between the elastic 3G
      // and a slope far below the answer (a heated bar: 3G, 2.2e9, 3G, ... and a step cut back
      // four times). The report's (2.34) does not say what to do then. Both forms have the
      // curve as their fixed point, and for a held strain the stress form's secant (2.33) is
      // the answer at once: a point whose secant changes direction takes the stress form for
      // the rest of the step (measured, the issue-16 cases with curve_form: strain: 6 of 12
      // failed after cut-backs, 1 does now).
      change = new_tan - it.tan_beta;
      stress_form = change * it.secant_change < 0 &&
                    std::abs(it.secant_change) > 1e-6 * std::abs(it.tan_beta);
      // A negative secant (the point starts the step above the curve, below) sets λ off the
      // curve's side in (2.34) and makes D̃ indefinite; the stress form's iterate does not
      // depend on the slope: the point takes it (both forms have the curve as fixed point).
      stress_form = stress_form || new_tan < 0;
    }
    double matrix_tan = new_tan;  // the slope of D̃ for the next solve
    if (stress_form) {  // (2.33)
      const auto ph = ps.curve.phi(a.eps0 + a.xt, right);
      if (!defects_set) {  // not where the strain form gave them (a point turning now)
        u.defect_sigma = ph.value - (a.q0 + ds);
        u.defect_eps = a.xt - it.x_prev;
      }
      new_tan = stress_secant(ps, a.eps0, a.q0, a.xt, ph.value, right);
      lambda = a.xt - (ph.value - a.q0) / three_g;
      // A stress at t above the curve along this step's direction Z makes the secant
      // negative for the increments that do not reach the curve again, and D̃ indefinite (the
      // matrix failed to factorize: tests/cli/inputs/issue16/indentation-unload). It happens
      // where an earlier step's stress turned away from its Z, as under an indenter: the
      // stress form puts σ's component along that Z on the curve, so the von Mises stress
      // σ̃(t) = Zᵀσ(t) of the next step's Z lies above it. The iterate above is the curve's
      // all the same (the point relaxes onto it along Z); only the matrix needs a slope, and
      // the curve's own slope there is the secant's limit from a point on the curve. The
      // secant itself stays the scheme's memory: Δσ̃ of the next iterate (the measure) is
      // the stress change it gives.
      matrix_tan = new_tan < 0 ? ph.slope : new_tan;
    }
    // A softening curve (a negative slope) leaves D̃ indefinite: the scheme has no answer.
    u.negative_secant = matrix_tan < 0;
    // Across Z the answer scales the trial deviator by θ = σ̃/σ̃_tr = 1 − 3Gλ/σ̃_tr (the radial
    // return), so an iterate's stress there changes by 2Gθ per unit strain, not D's 2G: where
    // the stress turns within the step (under an indenter), D̃'s stiffer response across Z
    // undershot by 1 − θ per iteration. D̃ takes θ across Z and keeps the secant along it
    // (the ball indentation: 244 -> 78 iterations, newton 37; docs/schemes.md).
    const double theta =
        lambda > 0 && q_tr > 0 ? std::clamp(1 - three_g * lambda / q_tr, 0.0, 1.0) : 1.0;
    u.tangent = d_tilde(k1, a.z, matrix_tan, theta);
    finish(k1, ps, it, sigma0, a, lambda, ds, new_tan, it.e0, u);
    u.next.stress_form = stress_form;
    u.next.secant_change = change;
    return u;
  }

 protected:
  double initial_tan_beta(double tan0, double) const override { return tan0; }

 private:
  bool strain_form_;
};

}  // namespace

std::unique_ptr<Scheme> make_scheme(SchemeKind kind, CurveForm form, double omega) {
  switch (kind) {
    case SchemeKind::newton:
      return std::make_unique<Newton>();
    case SchemeKind::variable_stiffness:
      return std::make_unique<VariableStiffness>(form == CurveForm::strain);
    case SchemeKind::initial_strain:
    case SchemeKind::initial_strain_stiffness:
      return scheme_law::make_initial_strain(kind == SchemeKind::initial_strain_stiffness, omega);
    case SchemeKind::initial_stress:
    case SchemeKind::initial_stress_stiffness:
      return scheme_law::make_initial_stress(kind == SchemeKind::initial_stress_stiffness);
  }
  HENCKY_VERIFY(false, "unknown scheme");
}

std::unique_ptr<Scheme> make_scheme(const SolverSpec& s) {
  return s.report ? make_report_scheme(s.scheme, s.curve_form, s.relaxation)
                  : make_scheme(s.scheme, s.curve_form, s.relaxation);
}

}  // namespace hencky
