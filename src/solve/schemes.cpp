#include "solve/schemes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hencky {

PointStep Scheme::begin_point_step(const ElasticConstants& k1, const Hardening& h, double T1,
                                   bool elastic_unloading, const Voigt& sigma0, double eps_p0,
                                   bool flowing, PointIteration& it) const {
  PointStep ps;
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

PointIteration Scheme::start_iteration(const PointStep& ps) const {
  PointIteration it;
  it.tan_beta = initial_tan_beta(ps.tan0, ps.curve.three_g);
  it.plastic_prev = false;
  it.tan_start = ps.tan0;
  return it;
}

namespace {

/// The size below which an increment of ε̃^{e+p} is round-off relative to ε̃^{e+p}(t) = `eps0`
/// (a purely volumetric increment, e.g. a thermal predictor, has ZᵀDx = 0 to round-off).
double strain_roundoff(const PointStep& ps, double eps0) {
  return 1e-8 * std::max(std::abs(eps0), ps.curve.eps_yield_now);
}

/// The secant of the curve over the step, (Φ(ε̃ + Δε̃) − σ̃)/Δε̃ with Φ(ε̃ + Δε̃) = `phi_value`:
/// tan β* of (2.33) and tan β** of (2.42). It is a difference of two numbers of the size of σ̃
/// divided by Δε̃: for an increment at round-off level it is noise of any sign and size (which
/// made D̃ indefinite at thermal predictors); its limit there is the curve's slope.
double stress_secant(const PointStep& ps, double eps0, double q0, double xt, double phi_value,
                     bool right) {
  return std::abs(xt) > strain_roundoff(ps, eps0) ? (phi_value - q0) / xt
                                                  : ps.curve.phi(eps0, right).slope;
}

}  // namespace

namespace {

/// What the five schemes of the report share once an iterate is evaluated along Z: the point
/// moves along the flow direction z of the step, from ε̃^{e+p}(t) = eps0 by xt.
struct AlongZ {
  Voigt z;
  double q0 = 0;    ///< σ̃(t) seen along Z
  double eps0 = 0;  ///< ε̃^{e+p}(t)
  double xt = 0;    ///< Δε̃^{e+p}_k = ZᵀDx / 3G
  Voigt dx;         ///< D x
};

/// The iterate seen along the direction z (a.dx already set).
void take_direction(AlongZ& a, const Voigt& z, const PointStep& ps, const Voigt& sigma0) {
  a.z = z;
  a.q0 = a.z.dot(sigma0);
  a.eps0 = ps.curve.eps_p + a.q0 / ps.curve.three_g;
  a.xt = a.z.dot(a.dx) / ps.curve.three_g;
}

/// The iterate x seen along the direction of its trial stress σ(t) + Dx, as the radial return
/// takes it: Z = Mσ/σ̃ of the answer, so the answer lies on the yield surface and is newton's
/// (backward Euler) to the tolerance on any path, with every scheme. The report's (2.10) takes
/// Z(t) = Mσ(t)/σ̃(t), fixed over the step: the stress lands on the curve along Z(t) and its
/// part across Z(t) stays elastic, so where the stress turns within a step the answer lies
/// above the yield surface (the ball indentation's contact edge: von Mises 1.3-7.7 times the
/// yield stress at t = 1 with variable-stiffness, its ball force 26 % above newton's; the
/// initial strains 23-30 % from newton's dent). Z(t) remains the direction of the `-stiffness`
/// schemes' matrix D̃(β*_0) (PointStep::z).
AlongZ along_z(const ElasticConstants& k1, const PointStep& ps, const Voigt& sigma0,
               const Voigt& x) {
  AlongZ a;
  a.dx = Tangent{}.times(k1, x);
  take_direction(a, flow_direction(sigma0 + a.dx), ps, sigma0);
  return a;
}

/// The `-stiffness` schemes (2.38)-(2.40), (2.44)-(2.46) fix tan β* at "the slope at the start of
/// the step", which for a point that was flowing depends on the direction the step takes: the
/// curve's loading slope if it keeps flowing, the elastic line 3G if it unloads (elastic
/// unloading). The report leaves the choice open; the loading slope is taken at the start, and
/// once the first iterates (the predictor, and the first solve: the matrix may then be refactored
/// once more) show the point unloading, 3G. With the loading slope kept, the fixed-matrix
/// iteration at an unloading point multiplies its error by 1 − 3G/tan β*_0 and diverges.
/// Unloading is seen along the direction of the start of the step, Z(t) (the matrix's): the
/// iterate's own direction turns over with a trial stress that passes through zero. A decrease
/// at round-off level is not unloading.
/// Returns true when it switched.
bool start_slope_on_unloading(const PointStep& ps, PointIteration& it, const AlongZ& a,
                              const Voigt& sigma0) {
  if (!ps.flowing || !ps.curve.elastic_unloading || it.k > 1 || it.tan_start == ps.curve.three_g)
    return false;
  const double three_g = ps.curve.three_g;
  const double eps0 = ps.curve.eps_p + ps.z.dot(sigma0) / three_g;
  if (!(ps.z.dot(a.dx) / three_g < -strain_roundoff(ps, eps0))) return false;
  it.tan_start = ps.curve.three_g;
  return true;
}

/// The stress and plastic state of the iterate from the plastic multiplier `lambda` along Z,
/// and the scheme's memory for the next iteration (ds: Δσ̃_k; new_tan: tan β of k+1; e0:
/// the initial strain of k+1).
void finish(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
            const Voigt& sigma0, const AlongZ& a, double lambda, double ds, double new_tan,
            const Voigt& e0, PointUpdate& u) {
  // Round-off on the elastic line is not plastic flow.
  if (std::abs(lambda) <= 1e-12 * std::max(std::abs(a.eps0 + a.xt), ps.curve.eps_yield_now))
    lambda = 0;
  u.z = a.z;
  u.d_lambda = lambda;
  u.plastic = lambda != 0;
  u.sigma = sigma0 + a.dx - lambda * Tangent{}.times(k1, a.z);  // σ(t) + D(x − Zλ)
  u.eps_ep = a.eps0 + a.xt;
  // A point elastic in this iterate and the one before follows the linear law exactly: its
  // curve defects vanish to round-off and a change between iterations says nothing about the
  // curve, so it does not enter the measures (an elastic step converges in one solve).
  if (!u.plastic && !it.plastic_prev) u.defect_sigma = u.defect_eps = 0;
  u.next = it;
  u.next.x_prev = a.xt;
  u.next.ds_prev = ds;
  u.next.tan_beta = new_tan;
  u.next.e0 = e0;
  u.next.plastic_prev = u.plastic;
  ++u.next.k;
}

/// The reference: the radial return with its consistent tangent.
class Newton final : public Scheme {
 public:
  SchemeKind kind() const override { return SchemeKind::newton; }
  MatrixPolicy matrix_policy() const override { return MatrixPolicy::per_iteration; }
  PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
                       const Voigt& sigma0, const Voigt& x) const override {
    const double three_g = ps.curve.three_g;
    const Voigt dx = Tangent{}.times(k1, x);  // D x
    PointUpdate u;
    const ReturnMapping rr = radial_return(k1, ps.curve, sigma0, x);
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
                       const Voigt& sigma0, const Voigt& x) const override {
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
/// (Equilibrium::mix); mixing the scalar λ0 while Z turned had doubled the residual every
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
                       const Voigt& sigma0, const Voigt& x) const override {
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
                       const Voigt& sigma0, const Voigt& x) const override {
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

std::unique_ptr<Scheme> make_scheme(SchemeKind kind, CurveForm form, double omega) {
  switch (kind) {
    case SchemeKind::newton:
      return std::make_unique<Newton>();
    case SchemeKind::variable_stiffness:
      return std::make_unique<VariableStiffness>(form == CurveForm::strain);
    case SchemeKind::initial_strain:
    case SchemeKind::initial_strain_stiffness:
      return std::make_unique<InitialStrain>(kind == SchemeKind::initial_strain_stiffness, omega);
    case SchemeKind::initial_stress:
    case SchemeKind::initial_stress_stiffness:
      return std::make_unique<InitialStress>(kind == SchemeKind::initial_stress_stiffness);
  }
  throw std::logic_error("unknown scheme");
}

}  // namespace hencky
