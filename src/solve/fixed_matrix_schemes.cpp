// The schemes with a matrix fixed within the step, 2-5 of the report: the initial strains
// (2.35)-(2.40) and the initial stresses (2.41)-(2.46), each with the elastic matrix or the
// start-of-step tangent (the `-stiffness` variants). The interface is solve/schemes.hpp.
#include <algorithm>
#include <cmath>

#include "solve/scheme_law.hpp"

namespace hencky::scheme_law {
namespace {

/// The schemes with a matrix fixed within the step (2-5): the elastic one, or the start-of-step
/// tangent (the `-stiffness` variants); Anderson mixing applies to all four.
class FixedMatrixScheme : public Scheme {
 public:
  FixedMatrixScheme(SchemeKind kind, bool stiffness) : kind_(kind), stiffness_(stiffness) {}
  SchemeKind kind() const override { return kind_; }
  MatrixPolicy matrix_policy() const override {
    return stiffness_ ? MatrixPolicy::per_step : MatrixPolicy::elastic;
  }
  bool allows_acceleration() const override { return true; }

 protected:
  bool stiffness() const { return stiffness_; }
  /// The iterate along its direction; with the `-stiffness` matrix, the first iterate of a point
  /// that unloads (start_slope_on_unloading, which switches `it` to 3G) and whose trial stress
  /// has passed through zero (σ(t) points against the trial's direction) is taken along Z(t)
  /// instead. That iterate came from the loading tangent and overshoots the elastic unloading
  /// by 3G/tan β*_0 (a hundredfold for a curve hardening at a hundredth of 3G): its trial stress
  /// lands on the far side of the yield surface, where the radial return would
  /// yield it in reverse, and from there the elastic matrix takes it back by the factor
  /// 1 − tan β/3G per iteration (unload-force, initial-stress-stiffness: 64 iterations in the
  /// first unloading step with Anderson's fallback every third one, against 10 for the whole
  /// run). Along Z(t) it lies on the elastic line, and the next solve, with 3G, lands on the
  /// elastic answer.
  AlongZ along_z_of_fixed_matrix(const ElasticConstants& k1, const PointStep& ps,
                                 PointIteration& it, const Voigt& sigma0, const Voigt& x) const {
    AlongZ a = along_z(k1, ps, sigma0, x);
    if (stiffness_ && start_slope_on_unloading(ps, it, a, sigma0) && a.q0 < 0)
      take_direction(a, ps.z, ps, sigma0);
    return a;
  }
  double initial_tan_beta(double tan0, double three_g) const override {
    return stiffness_ ? tan0 : three_g;
  }

 private:
  SchemeKind kind_;
  bool stiffness_;
};

/// Schemes 2 and 3, (2.35)-(2.37) and (2.38)-(2.40): initial strains on the curve's strain
/// form, relaxed by ω, with the elastic matrix (2) or the start-of-step tangent (3).
/// The report's initial strain is Z·λ0 with Z(t) fixed over the step; along the trial's Z,
/// which turns from one iteration to the next, it is a tensor Δε^0 (PointIteration::e0): each
/// iterate takes its multiplier λ_k along its own Z from the plastic strain that Δε^0 gives,
/// corrects it by ω times the curve's defect, and sets Δε^0 to give Zλ_{k+1}. The stress is
/// linear in the iterate for a fixed Δε^0, which Anderson's mixing of Δε^0 relies on
/// (Mixing::mix); mixing the scalar λ0 while Z turned had doubled the residual every
/// fourth iteration (the ball indentation stopped with status 2).
/// A held point (PointIteration::held) takes one branch of the curve whatever its iterate's
/// stress, and says when its stress lies beyond the yield stress by more than `hold_slack`
/// relative on the other side: a point at the yield stress to within a millionth has an
/// answer on either branch (their strains differ by the slack over the plastic slope).
class InitialStrain final : public FixedMatrixScheme {
 public:
  static constexpr double hold_slack = 1e-6;
  InitialStrain(bool stiffness, double omega)
      : FixedMatrixScheme(stiffness ? SchemeKind::initial_strain_stiffness
                                    : SchemeKind::initial_strain,
                          stiffness),
        omega_(omega) {}
  bool uses_strain_form() const override { return true; }
  bool iterates_initial_strain() const override { return true; }
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x,
                       const LawState& /*law*/) const override {
    const double three_g = ps.curve.three_g;
    PointIteration memory = it;
    AlongZ a = along_z_of_fixed_matrix(k1, ps, memory, sigma0, x);
    PointUpdate u;
    // A point found unloading at this iterate (start_slope_on_unloading) takes the elastic
    // line at once, with no initial strain: the next solve has the elastic matrix there.
    const bool switched = memory.tan_start != it.tan_start;
    const double tb = stiffness() ? memory.tan_start : three_g;
    // The matrix D̃(β*_0) = D − c·DZ₀Z₀ᵀD/3G softens D along the step's Z₀ = Z(t) by
    // c = 1 − tan β*_0/3G (c = 0: the elastic matrix). The iterate's stress σ(t) + D̃(x − Δε^0)
    // is σ(t) + D(x − Δε^p) with the plastic strain Δε^p = Δε^0 + c·Z₀·Z₀ᵀD(x − Δε^0)/3G, and
    // λ_k = ZᵀDΔε^p/3G is its multiplier along the iterate's Z (with Z = Z₀ the report's
    // λ0 + c(Δε̃ − λ0) of (2.25)).
    const double c = (three_g - tb) / three_g;
    Voigt plastic = switched ? Voigt::Zero() : it.e0;
    if (c != 0) plastic += c * (ps.z.dot(Tangent{}.times(k1, x - it.e0)) / three_g) * ps.z;
    // A point held plastic whose trial stress lies inside the yield surface flows backwards on
    // the continued branch (λ < 0): along its trial's Z, whose magnitude σ̃_tr = σ̃ − 3G|λ| can be
    // small, the direction turns by 3G|λ|/σ̃_tr times the change of the iterate across it,
    // more than once (the ball indentation, t = 0.25 → 0.5: the plain iteration cycled with
    // period two, its residual stuck at 1.4e-2). Along the direction of its stress with the
    // current Δε^0, σ̃ = σ̃_tr + 3G|λ|, the factor is below one. (Such a point leaves the held
    // set before the step converges: the answer is the radial return's all the same.)
    const Voigt d_plastic = Tangent{}.times(k1, plastic);
    if (it.held > 0 && a.q0 + three_g * a.xt < ps.curve.yield_now)
      take_direction(a, flow_direction(sigma0 + a.dx - d_plastic), ps, sigma0);
    const double lambda_k = a.z.dot(d_plastic) / three_g;
    const double ds = three_g * (a.xt - lambda_k);  // Δσ̃_k = Zᵀ(σ_k − σ(t))
    const double s = a.q0 + ds, y = ps.curve.yield_now;
    Hardening::Point fk;
    bool breaks_hold = false;
    if (it.held < 0) {  // the elastic line, also above the yield stress
      fk = {ps.curve.eps_p + s / three_g, 1 / three_g};
      breaks_hold = s > y * (1 + hold_slack);
    } else if (it.held > 0 && s < y) {  // the plastic branch, continued below the yield stress
      fk = ps.curve.f(y, true);
      fk.value += (s - y) * fk.slope;
      breaks_hold = s < y * (1 - hold_slack);
    } else {
      fk = ps.curve.f(s, ps.flowing || it.held > 0);
    }
    if (!std::isfinite(fk.value)) {
      // The iterate's stress is above the largest the curve reaches (a table's flat end),
      // where no strain belongs to it: the defect is taken at that largest stress, with the
      // slope of the curve below it, which raises λ0 and brings the stress down (measured: a
      // multilinear cube whose elastic iterates overshoot its table's end was cut back 40
      // times when such an iterate failed the step). The point is marked: an answer there,
      // a converged one or the last of a step that fails, has no strain form (the run stops
      // with the message that names the schemes that can).
      u.undefined = true;
      const double top = ps.curve.hardening->max_stress(ps.curve.temperature);
      fk = ps.curve.f(top * (1 - 1e-12), false);
    }
    u.defect_eps = fk.value - (a.eps0 + a.xt);
    u.defect_sigma = ds - it.ds_prev;
    // λ_{k+1} = λ_k + ω(F − ε̃). relaxation: auto (omega_ = 0) takes ω = 1/(tan β*·F'(σ̃_k))
    // (= tan β/3G with the elastic matrix) from the curve's slope tan β = 1/F' where the
    // iterate's stress is: the scalar Newton step of a point whose strain is held, which lands
    // it on a linear curve at once. A point held by its surroundings contracts by 1 − a·ω with
    // a between 1 (its stress held) and tan β*/tan β (its strain held): with this ω every
    // factor lies in [0, 1), half the stability bound (docs/schemes.md).
    const double omega = omega_ > 0 ? omega_ : std::min(1.0, 1.0 / (tb * fk.slope));
    // The report's λ0_{k+1} = λ0_k + ω(F − ε̃): along Z the plastic strain moves by (1 − c) of
    // it, (2.25).
    const double lambda = lambda_k + omega * (1 - c) * u.defect_eps;
    // Δε^0_{k+1}: the initial strain that gives the plastic strain Zλ at this x under D̃,
    // D̃(x − Δε^0) = D(x − Zλ): Δε^0 = Zλ − c/(1 − c)·Z₀·Z₀ᵀD(x − Zλ)/3G. (A start slope of 0,
    // c = 1, leaves D̃ without stiffness along Z₀: any component there gives the same stress.)
    Voigt e0 = lambda * a.z;
    if (c != 0 && c < 1)
      e0 -= c / (1 - c) * (ps.z.dot(Tangent{}.times(k1, x - e0)) / three_g) * ps.z;
    if (stiffness()) {
      // The initial strain gathered so far corrected the loading matrix; with the elastic one
      // an elastic unloading needs none (left in place it would only decay by 1 − ω per
      // iteration).
      if (switched) e0.setZero();
      u.tangent = d_tilde(k1, ps.z, memory.tan_start);
    }
    finish(k1, ps, memory, sigma0, a, lambda, ds, it.tan_beta, e0, u);
    u.next.breaks_hold = breaks_hold;
    return u;
  }

 private:
  double omega_;
};

/// Schemes 4 and 5, (2.41)-(2.43) and (2.44)-(2.46): initial stresses on the curve's stress
/// form, with the elastic matrix (4) or the start-of-step tangent (5).
class InitialStress final : public FixedMatrixScheme {
 public:
  explicit InitialStress(bool stiffness)
      : FixedMatrixScheme(stiffness ? SchemeKind::initial_stress_stiffness
                                    : SchemeKind::initial_stress,
                          stiffness) {}
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x,
                       const LawState& /*law*/) const override {
    const double three_g = ps.curve.three_g;
    PointIteration memory = it;
    const AlongZ a = along_z_of_fixed_matrix(k1, ps, memory, sigma0, x);
    const bool right = ps.flowing;
    PointUpdate u;
    const double tb = stiffness() ? it.tan_start : three_g;
    // Δσ̃_k of the solve with D̃(β*) and Δσ^0_k = (D̃(β**_k) − D̃(β*))x_{k−1}
    const double ds = tb * a.xt + (it.tan_beta - tb) * it.x_prev;
    const auto ph = ps.curve.phi(a.eps0 + a.xt, right);
    u.defect_sigma = ph.value - (a.q0 + ds);
    u.defect_eps = a.xt - it.x_prev;
    const double new_tan = stress_secant(ps, a.eps0, a.q0, a.xt, ph.value, right);  // β**_{k+1}
    // σ_k = D̃(β**_{k+1})x: on the curve along Z
    const double lambda = a.xt - (ph.value - a.q0) / three_g;
    if (stiffness()) {
      u.tangent = d_tilde(k1, ps.z, memory.tan_start);
    }
    finish(k1, ps, memory, sigma0, a, lambda, ds, new_tan, it.e0, u);
    return u;
  }
};

}  // namespace

std::unique_ptr<Scheme> make_initial_strain(bool stiffness, double omega) {
  return std::make_unique<InitialStrain>(stiffness, omega);
}

std::unique_ptr<Scheme> make_initial_stress(bool stiffness) {
  return std::make_unique<InitialStress>(stiffness);
}

}  // namespace hencky::scheme_law
