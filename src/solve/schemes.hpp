#pragma once
// The iteration schemes of the formulation (report 2.32-2.46) and the reference `newton`, as
// point laws. The equilibrium iteration (equilibrium.cpp) is written once in residual form:
//
//   K_k δ = F_target − F_int(σ_k),   Δu_{k+1} = Δu_k + δ,
//
// where σ_k is the stress each scheme assigns to the iterate Δu_k after updating its parameters
// (β*, Δε^0, Δσ^0) from it, and K_k the matrix of the scheme. With σ_k = D̃(β*)(Δε_k − Δε^th −
// Δε^0) + Δσ^0 this is algebraically the report's equation (2.29) for iteration k+1 (the terms
// K_kΔu_k cancel), with the error correction (2.30) in F_target. docs/schemes.md derives this.
//
// Two sets of point laws run in that loop (solver.formulation). The report's five schemes as
// written (formulation: report) are in report_schemes.cpp. hencky's (the default), here and in
// fixed_matrix_schemes.cpp, are not the report's iteration: they take the iterate's own flow
// direction and add strategies of their own (docs/schemes.md, "Two formulations"), and all
// share one converged point law: the stress, projected on the flow direction Z, lands on the
// curve, Zᵀσ(t+Δt) = Φ(ε̃^{e+p}(t) + Δε̃^{e+p}), with the plastic strain increment along Z:
// newton's radial return. They differ in the path: which matrix (elastic D, the start-of-step
// tangent D̃(β*_0), or the secant D̃(β*_k) rebuilt every iteration) and which pseudo-load
// corrects the defect (initial strains in F-form, initial stresses in Φ-form).
//
// Definitions the report leaves open, as hencky's schemes take them (docs/schemes.md):
// - the scalar increment Δε̃^{e+p} of a strain increment x = Δε − Δε^th is its projection
//   ZᵀDx / 3G (signed): the scalar the matrix D̃ of (2.9) works with, since ZᵀD̃x = tanβ*·ZᵀDx/3G;
// - ε̃^{e+p}(t) at the start of a step is ε̃^p(t) + Zᵀσ(t)/3G(t+Δt): the advanced scalar on
//   proportional paths, kept consistent with the actual stress on others and after reversals;
// - Z is the direction of the iterate's elastic trial stress σ(t) + Dx (as the radial return
//   takes it), so the answer lies on the yield surface and equals newton's on any path
//   (`along_z`, solve/scheme_law.hpp); the report's Mσ(t)/σ̃(t) (2.10) stays the direction of the
//   `-stiffness` matrix. The initial strains therefore carry a tensor Δε^0, not Zλ0: their
//   Z turns from one iteration to the next. With the trial's Z, and ε̃^{e+p}(t) = ε̃^p(t) + Zᵀσ(t)/3G
//   below, ε̃^{e+p}(t) + Δε̃^{e+p} is ε̃^p(t) + σ̃_tr/3G: the curve's point Φ of the radial return.
#include <memory>
#include <span>
#include <string>

#include "material/plastic_point.hpp"
#include "material/point_law.hpp"
#include "spec/case.hpp"

namespace hencky {

/// When the scheme's matrix changes (the step loop assembles and factorizes it again).
enum class MatrixPolicy {
  per_iteration,  ///< newton, variable-stiffness: whenever a point's matrix changed
  per_step,       ///< the `-stiffness` schemes: the start-of-step tangent (a second one at
                  ///< the first iteration when flowing points turn out to unload, tan_start)
  elastic,        ///< initial-strain, initial-stress: the elastic matrix, rebuilt only when
                  ///< E or ν change with the temperature
};

/// A point law's internal variables at a point (PointLaw::variables; empty for the isotropic
/// law): at t, and at the iterate, which the point law writes.
struct LawState {
  std::span<const double> at_t;
  std::span<double> now;
};

/// A point's state at the start of a step, t, as the schemes start from it.
struct PointAtT {
  Voigt sigma = Voigt::Zero();  ///< σ(t) (τ(t) under `updated`)
  double eps_p = 0;             ///< ε̃^p(t)
  double eps_ep = 0;            ///< ε̃^{e+p}(t): the scalar the report's schemes advance
  double eps_ep_max = 0;        ///< the largest ε̃^{e+p} reached (the report's elastic unloading)
  bool flowing = false;         ///< the point flowed plastically in the step that ended at t
};

/// What a point keeps fixed during one step.
struct PointStep {
  const PointLaw* law = nullptr;  ///< the material's point law
  StepCurve curve;          ///< the curve at t+Δt, with elastic unloading from ε̃^p(t)
  Voigt z = Voigt::Zero();  ///< Mσ(t)/σ̃(t) when flowing at t, else zero (from the trial)
  bool flowing = false;     ///< the point flowed plastically in the step that ended at t
  double tan0 = 0;          ///< tan β*_0: the curve's slope at the start of the step
  double eps_ep = 0;        ///< ε̃^{e+p}(t) (formulation: report; hencky's derives it from σ(t))
};

/// The scheme's memory from one iteration to the next (discarded with the step).
struct PointIteration {
  double tan_beta = 0;  ///< tan β*_k (variable stiffness) or tan β**_k (initial stresses)
  /// The initial strains' Δε^0_k, relative to the scheme's matrix: the iterate's stress is
  /// σ(t) + D̃(x − Δε^0) (D̃ = D with the elastic matrix). A tensor, since the trial's Z turns
  /// from one iteration to the next (with Z fixed it is Z·λ0 of (2.35)).
  Voigt e0 = Voigt::Zero();
  double lambda0 = 0;   ///< formulation: report: the initial strain Δε^0_k = Z·λ0 of (2.37)
  double x_prev = 0;    ///< Δε̃^{e+p}_{k−1}
  double ds_prev = 0;   ///< Δσ̃_{k−1}
  bool plastic_prev = false;
  /// The `-stiffness` schemes' matrix slope tan β*_0: the curve's loading slope at the start of
  /// the step, or 3G once the first iterate shows that a flowing point unloads (elastic
  /// unloading): the loading tangent is far softer than that response and the fixed-matrix
  /// iteration would diverge (its factor at the point is 1 − 3G/tan β*_0).
  double tan_start = 0;
  /// variable-stiffness on the strain form: the last change of tan β*, and whether the point
  /// has turned to the stress form in this step (its secant alternated).
  double secant_change = 0;
  bool stress_form = false;
  /// The initial-strain schemes: the point's status held by the equilibrium iteration (an
  /// active set, PointPass::hold_plastic_set): 0 free, +1 held plastic (the curve's plastic
  /// branch, continued below the yield stress), −1 held elastic (the elastic line, continued
  /// above it).
  signed char held = 0;
  /// A held point whose last iterate the free law would take to the other status: held
  /// plastic below the yield stress, held elastic above it.
  bool breaks_hold = false;
  int k = 0;  ///< iterations evaluated in this step
};

/// Everything the evaluation of one iterate gives back.
struct PointUpdate {
  Voigt sigma = Voigt::Zero();  ///< σ_k
  Voigt z = Voigt::Zero();      ///< the flow direction used
  double d_lambda = 0;          ///< total plastic multiplier: Δε^p = z·d_lambda
  double eps_ep = 0;            ///< ε̃^{e+p}(t) + Δε̃^{e+p}_k
  Tangent tangent;              ///< the scheme's matrix at this point for the next solve
  bool plastic = false;         ///< plastic flow in this iterate
  double defect_sigma = 0, defect_eps = 0;  ///< numerators of Δ^σ_k, Δ^ε_k
  bool undefined = false;  ///< the iterate needed F above the curve's largest stress (taken there)
  bool negative_secant = false;  ///< variable-stiffness: the secant slope is negative
  PointIteration next;           ///< the scheme's memory for iteration k+1
};

/// The memory of the next iteration after iterate `u` (from the memory `it`; xt = Δε̃_k,
/// ds = Δσ̃_k, tan_beta: tan β of k+1). A point elastic in this iterate and the one before
/// follows the linear law exactly: its curve defects vanish to round-off and a change between
/// iterations says nothing about the curve (it is the residual's), so its measures are dropped
/// (an elastic step converges in one solve; a body unloaded to no stress does not divide
/// round-off by a vanishing σ̃).
void remember_iterate(PointUpdate& u, const PointIteration& it, double xt, double ds,
                      double tan_beta);

/// One scheme: the start of a step at a point, the point law, when the matrix changes and
/// whether acceleration applies. The six implementations are in schemes.cpp (newton,
/// variable-stiffness) and fixed_matrix_schemes.cpp (the initial strains and stresses).
class Scheme {
 public:
  virtual ~Scheme() = default;
  virtual SchemeKind kind() const = 0;
  const char* name() const { return scheme_name(kind()); }
  virtual MatrixPolicy matrix_policy() const = 0;
  /// Anderson mixing applies: a fixed matrix within the step (not newton and
  /// variable-stiffness, whose matrix changes every iteration).
  virtual bool allows_acceleration() const { return false; }
  /// The iterated state is the initial strain Δε^0 the points carry from one iteration to the
  /// next (PointIteration::e0), which the displacements follow: Anderson mixes Δε^0 (the
  /// initial-strain schemes). Otherwise the iterate is the displacement alone.
  virtual bool iterates_initial_strain() const { return false; }
  /// Uses the curve's strain form F = ε(σ) (undefined above the curve's largest stress).
  virtual bool uses_strain_form() const { return false; }

  /// Sets up a point for a step: direction, start slope, the scheme's initial parameters.
  virtual PointStep begin_point_step(const ElasticConstants& k1, const PointLaw& law,
                                     const Hardening& h, double T1, bool elastic_unloading,
                                     const PointAtT& at, PointIteration& it) const;
  /// The same from σ(t), ε̃^p(t) and whether the point flowed (hencky's schemes need no more).
  PointStep begin_point_step(const ElasticConstants& k1, const PointLaw& law, const Hardening& h,
                             double T1, bool elastic_unloading, const Voigt& sigma0, double eps_p0,
                             bool flowing, PointIteration& it) const {
    PointAtT at;
    at.sigma = sigma0;
    at.eps_p = eps_p0;
    at.flowing = flowing;
    return begin_point_step(k1, law, h, T1, elastic_unloading, at, it);
  }

  /// The scheme's memory before the first iterate of the step (also after an elastic start:
  /// that solve took nothing from the point law).
  PointIteration start_iteration(const PointStep& ps) const;

  /// The point law: evaluates iterate k at a point, x = Δε_k − Δε^th, from the point's state
  /// at t (sigma0, ps) and the scheme's memory `it`. Returns the stress σ_k, the plastic
  /// increment, the matrix for the next solve, the defect measures and the memory of the next
  /// iteration; a pure function of its arguments but for `law.now`, the law's state at the
  /// iterate, which it writes (newton, through PointLaw::update; the report's schemes run only
  /// the isotropic law, which has none).
  virtual PointUpdate evaluate(const ElasticConstants& k1, const PointStep& ps,
                               const PointIteration& it, const Voigt& sigma0, const Voigt& x,
                               const LawState& law) const = 0;
  /// formulation: report: the iterate x with the scheme's initial parameters of the step
  /// (β*_0, Δε^0_0 = 0, Δσ^0_0 = 0), σ = σ(t) + D̃(β*_0)x, and its matrix, the memory `it`
  /// unchanged: what the report's first solve of a step is made of (its first right-hand side
  /// carries the prescribed displacements' and thermal strains' part of x through D̃(β*_0)).
  /// Only the report's schemes have it (has_initial_evaluation).
  virtual PointUpdate evaluate_initial(const ElasticConstants& k1, const PointStep& ps,
                                       const PointIteration& it, const Voigt& sigma0,
                                       const Voigt& x) const;
  /// The yield stress the state of an iterate stands for (the admissibility check σ̃ ≤ it):
  /// H(ε̃^p, T) at t+Δt, the surface of hencky's schemes; the report's schemes override it.
  virtual double yield_stress(const PointStep& ps, double eps_p, double eps_ep,
                              double eps_ep_max) const;
  /// The scheme is one of the report's as written (formulation: report): its step starts from
  /// evaluate_initial and it has none of hencky's additions.
  virtual bool has_initial_evaluation() const { return false; }

 protected:
  /// tan β of iteration 0 at a point whose start slope is tan0.
  virtual double initial_tan_beta(double tan0, double three_g) const {
    (void)tan0;
    return three_g;  // β* = β^e; Δσ^0_0 = 0 means β**_0 = β*
  }
};

/// The schemes that do not use the curve's strain form, for messages about curves that have none
/// (flat from their yield point, or beyond a table's end).
inline constexpr const char* schemes_without_strain_form =
    "newton, initial-stress, initial-stress-stiffness, and variable-stiffness with curve_form: "
    "stress";

/// The scheme of the case: `form` for variable-stiffness, `omega` the relaxation of the
/// initial-strain schemes.
std::unique_ptr<Scheme> make_scheme(SchemeKind kind, CurveForm form, double omega);
/// The scheme of the solver section: hencky's (make_scheme above) or, under `formulation:
/// report`, the report's as written (solve/report_schemes.cpp).
std::unique_ptr<Scheme> make_scheme(const SolverSpec& s);
/// The report's schemes as written (newton is none of them: refused by the case reader).
std::unique_ptr<Scheme> make_report_scheme(SchemeKind kind, CurveForm form, double omega);

}  // namespace hencky
