#include "solve/schemes.hpp"

#include <cassert>
#include <cmath>
#include <stdexcept>

namespace hencky {

namespace {
struct Name {
  SchemeKind kind;
  const char* name;
};
constexpr Name names[] = {
    {SchemeKind::newton, "newton"},
    {SchemeKind::variable_stiffness, "variable-stiffness"},
    {SchemeKind::initial_strain, "initial-strain"},
    {SchemeKind::initial_strain_stiffness, "initial-strain-stiffness"},
    {SchemeKind::initial_stress, "initial-stress"},
    {SchemeKind::initial_stress_stiffness, "initial-stress-stiffness"},
};
}  // namespace

SchemeKind scheme_from_name(const std::string& name) {
  for (const auto& n : names)
    if (name == n.name) return n.kind;
  throw std::logic_error("unknown scheme '" + name + "' (the case reader admits only known ones)");
}

const char* scheme_name(SchemeKind kind) {
  for (const auto& n : names)
    if (kind == n.kind) return n.name;
  return "?";
}

PointStep begin_point_step(const SchemeOptions& s, const ElasticConstants& k1, const Hardening& h,
                           double T1, bool elastic_unloading, const Voigt& sigma0, double eps_p0,
                           bool flowing, PointIteration& it) {
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
    if (s.uses_strain_form()) {
      // tan β*_0 = 1 / F'(σ̃(t)), (2.34), (2.40); 0 where F is flat-ended (perfect plasticity).
      const double df = ps.curve.f(q0, true).slope;
      ps.tan0 = std::isfinite(df) && df > 0 ? 1 / df : 0.0;
    } else {
      // tan β*_0 = Φ'(ε̃(t)), (2.33), (2.46)
      ps.tan0 = ps.curve.phi(eps_p0 + q0 / three_g, true).slope;
    }
  }
  it = PointIteration{};
  switch (s.kind) {
    case SchemeKind::variable_stiffness:
    case SchemeKind::initial_strain_stiffness:
    case SchemeKind::initial_stress_stiffness:
      it.tan_beta = ps.tan0;
      break;
    default:
      it.tan_beta = three_g;  // β* = β^e; Δσ^0_0 = 0 means β**_0 = β*
  }
  it.plastic_prev = false;
  it.tan_start = ps.tan0;
  return ps;
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

/// The `-stiffness` schemes (2.38)-(2.40), (2.44)-(2.46) fix tan β* at "the slope at the start of
/// the step", which for a point that was flowing depends on the direction the step takes: the
/// curve's loading slope if it keeps flowing, the elastic line 3G if it unloads (elastic
/// unloading). The report leaves the choice open; the loading slope is taken at the start, and
/// once the first iterates (the predictor, and the first solve: the matrix may then be refactored
/// once more) show the point unloading, 3G. With the loading slope kept, the fixed-matrix
/// iteration at an unloading point multiplies its error by 1 − 3G/tan β*_0 and diverges.
/// `xt` is the iterate's Δε̃^{e+p}; `eps0` ε̃^{e+p}(t). A decrease at round-off level is not
/// unloading.
/// Returns true when it switched.
bool start_slope_on_unloading(const PointStep& ps, PointIteration& it, double xt, double eps0) {
  if (!ps.flowing || !ps.curve.elastic_unloading || it.k > 1 || it.tan_start == ps.curve.three_g ||
      !(xt < -strain_roundoff(ps, eps0)))
    return false;
  it.tan_start = ps.curve.three_g;
  return true;
}

}  // namespace

PointUpdate evaluate_point(const SchemeOptions& s, const ElasticConstants& k1, const PointStep& ps,
                           PointIteration& it, const Voigt& sigma0, const Voigt& x) {
  const double three_g = ps.curve.three_g;
  const Tangent elastic;
  const Voigt dx = elastic.times(k1, x);  // D x
  PointUpdate u;

  if (s.kind == SchemeKind::newton) {
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
    it.ds_prev = q - q0;
    it.x_prev = xt;
    it.plastic_prev = u.plastic;
    ++it.k;
    return u;
  }

  // Z of the step; for a point elastic at t, the direction of the elastic trial stress.
  const Voigt z = ps.flowing ? ps.z : flow_direction(sigma0 + dx);
  const double q0 = z.dot(sigma0);                    // σ̃(t) seen along Z
  const double eps0 = ps.curve.eps_p + q0 / three_g;  // ε̃^{e+p}(t)
  const double xt = z.dot(dx) / three_g;              // Δε̃^{e+p}_k = ZᵀDx / 3G
  const bool right = ps.flowing;
  double lambda = 0, ds = 0, new_tan = it.tan_beta, lambda0 = it.lambda0;

  switch (s.kind) {
    case SchemeKind::variable_stiffness:
      ds = it.tan_beta * xt;  // Δσ̃_k of the solve with D̃(β*_k)
      if (!s.strain_form) {   // (2.33)
        const auto ph = ps.curve.phi(eps0 + xt, right);
        u.defect_sigma = ph.value - (q0 + ds);
        u.defect_eps = xt - it.x_prev;
        new_tan = stress_secant(ps, eps0, q0, xt, ph.value, right);
        lambda = xt - (ph.value - q0) / three_g;
      } else {  // (2.34)
        const auto fk = ps.curve.f(q0 + ds, right);
        if (!std::isfinite(fk.value)) {
          u.undefined = true;
          return u;
        }
        u.defect_eps = fk.value - (eps0 + it.x_prev);
        u.defect_sigma = ds - it.ds_prev;
        const double den = fk.value - eps0;
        // As above: the secant Δσ̃/(F(σ̃ + Δσ̃) − ε̃) is noise for Δσ̃ at round-off level.
        new_tan = std::abs(ds) > 1e-8 * std::max(std::abs(q0), ps.curve.yield_now) && den != 0
                      ? ds / den
                      : 1 / fk.slope;
        lambda = (three_g - new_tan) / three_g * xt;
      }
      // A stress at t above the curve along this step's direction Z (left by an earlier step
      // whose stress turned away from its Z, as under an indenter) makes the secant negative
      // and D̃ indefinite: the scheme has no answer for the step.
      u.negative_secant = new_tan < 0;
      u.tangent = d_tilde(k1, z, new_tan);
      break;

    case SchemeKind::initial_strain:              // (2.35)-(2.37)
    case SchemeKind::initial_strain_stiffness: {  // (2.38)-(2.40)
      const double tb = s.kind == SchemeKind::initial_strain ? three_g : it.tan_start;
      ds = tb * (xt - it.lambda0);  // Δσ̃_k = ZᵀD̃(β*)(x − Zλ0_k)
      const auto fk = ps.curve.f(q0 + ds, right);
      if (!std::isfinite(fk.value)) {
        u.undefined = true;
        return u;
      }
      u.defect_eps = fk.value - (eps0 + xt);
      u.defect_sigma = ds - it.ds_prev;
      lambda0 = it.lambda0 + s.omega * u.defect_eps;  // Δε^0_{k+1} = Δε^0_k + ω(F − ε̃)·Z
      // Δε^p = Ỹ(x − Zλ0) + Zλ0, (2.25): along Z, Ỹ contributes (3G − tanβ*)/3G of it.
      lambda = lambda0 + (three_g - tb) / three_g * (xt - lambda0);
      if (s.kind == SchemeKind::initial_strain_stiffness) {
        // The initial strain gathered so far corrected the loading matrix; with the elastic one
        // an elastic unloading needs none (left in place it would only decay by 1 − ω per
        // iteration).
        if (start_slope_on_unloading(ps, it, xt, eps0)) lambda0 = 0;
        u.tangent = d_tilde(k1, z, it.tan_start);
      }
      break;
    }

    case SchemeKind::initial_stress:              // (2.41)-(2.43)
    case SchemeKind::initial_stress_stiffness: {  // (2.44)-(2.46)
      const double tb = s.kind == SchemeKind::initial_stress ? three_g : it.tan_start;
      // Δσ̃_k of the solve with D̃(β*) and Δσ^0_k = (D̃(β**_k) − D̃(β*))x_{k−1}
      ds = tb * xt + (it.tan_beta - tb) * it.x_prev;
      const auto ph = ps.curve.phi(eps0 + xt, right);
      u.defect_sigma = ph.value - (q0 + ds);
      u.defect_eps = xt - it.x_prev;
      new_tan = stress_secant(ps, eps0, q0, xt, ph.value, right);  // β**_{k+1}
      lambda = xt - (ph.value - q0) / three_g;  // σ_k = D̃(β**_{k+1})x: on the curve along Z
      if (s.kind == SchemeKind::initial_stress_stiffness) {
        start_slope_on_unloading(ps, it, xt, eps0);
        u.tangent = d_tilde(k1, z, it.tan_start);
      }
      break;
    }
    case SchemeKind::newton:
      assert(false);
  }

  // Round-off on the elastic line is not plastic flow.
  if (std::abs(lambda) <= 1e-12 * std::max(std::abs(eps0 + xt), ps.curve.eps_yield_now)) lambda = 0;
  u.z = z;
  u.d_lambda = lambda;
  u.plastic = lambda != 0;
  u.sigma = sigma0 + dx - lambda * elastic.times(k1, z);  // σ(t) + D(x − Zλ)
  u.eps_ep = eps0 + xt;
  // A point elastic in this iterate and the one before follows the linear law exactly: its
  // curve defects vanish to round-off and a change between iterations says nothing about the
  // curve, so it does not enter the measures (an elastic step converges in one solve).
  if (!u.plastic && !it.plastic_prev) u.defect_sigma = u.defect_eps = 0;
  it.x_prev = xt;
  it.ds_prev = ds;
  it.tan_beta = new_tan;
  it.lambda0 = lambda0;
  it.plastic_prev = u.plastic;
  ++it.k;
  return u;
}

}  // namespace hencky
