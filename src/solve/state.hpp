#pragma once
// What the step loop works on and reports: the state of the body at a converged time or at an
// iterate, a converged step's report, the run's timings, and the observer that sees every
// converged step.
#include <cmath>
#include <cstdint>
#include <vector>

#include "material/plastic_point.hpp"
#include "solve/model.hpp"

namespace hencky {

/// Everything that describes the body at one converged time (committed) or at the current
/// iterate (trial). Integration-point data is indexed by Model::point_offset(cell) + q and
/// holds this rank's cells only (all of them on one rank); nodal data is whole on every rank.
struct State {
  double time = 0;
  std::vector<double> u;                    ///< displacement, 3 per node
  std::vector<double> nodal_temperature;    ///< per node
  /// Heat section only: per heat.boundary entry, the heat into the body (W) at this time
  /// (HeatSnapshot::flow).
  std::vector<double> heat_flow;
  std::vector<Voigt> stress;                ///< per integration point
  std::vector<double> temperature;          ///< per integration point
  std::vector<ElasticConstants> constants;  ///< E, ν, α at the point's temperature
  std::vector<double> f_ext;                ///< external nodal forces, 3 per node
  std::vector<double> f_int;                ///< internal nodal forces ∫Bᵀσ, 3 per node
  // Plasticity, per integration point (zero for elastic materials):
  std::vector<Voigt> plastic_strain;  ///< ε^p, engineering shears
  std::vector<double> eps_p_eq;       ///< ε̃^p, equivalent plastic strain (hardening variable)
  std::vector<double> eps_ep;         ///< ε̃^{e+p}, the scalar the schemes advance
  std::vector<double> eps_ep_max;     ///< the largest ε̃^{e+p} reached
  std::vector<std::uint8_t> flowing;  ///< 1: flowed plastically in the step that ended here
  /// The point laws' internal variables (PointLaw::variables, e.g. the back stress):
  /// Model::law_state_size() numbers per point, from index p·law_state_size(); empty when no
  /// law has any.
  std::vector<double> internal;
  // Contact (report section 3):
  std::vector<double> f_contact;  ///< forces of the rigid supports on the nodes, 3 per node
  std::vector<std::vector<ContactNode>> contact;  ///< per contact, per contact point
  /// The force history (Equilibrium::history_force): ∫ f dt over the converged steps from
  /// t = 0, with f the force scale of each step.
  double force_integral = 0;
};

/// What the equilibrium iteration carries from one converged step into the next besides the
/// State (Equilibrium::memory): a restart puts it back so that the steps after it are those of
/// the run that was not interrupted, to the last bit. Point data: this rank's points.
struct EquilibriumMemory {
  /// newton's predictor (solver.predictor): the last converged increment of the free unknowns
  /// and its Δt (0: none yet).
  std::vector<double> last_du;
  double last_dt = 0;
  /// A matrix is factorized; it was assembled from `assembled_tangents` (the points' matrices,
  /// plastic materials only) and, with contact, the contact states `assembled_contact`.
  bool factorized = false;
  std::vector<Tangent> assembled_tangents;
  std::vector<std::vector<ContactNode>> assembled_contact;
  /// The points' matrices of the last iterate (what the next one's are compared with).
  std::vector<Tangent> tangents;
};

/// One target of the step control: a time and its cut-back depth.
struct StepTarget {
  double time = 0;
  int depth = 0;
};

/// The largest of a value over the integration points, with the cell's node nearest that point
/// (its file number) and the point's position in the undeformed mesh.
struct PointLargest {
  double value = -INFINITY;  ///< −inf: no point
  long node = 0;
  Vec3 x = Vec3::Zero();
};

/// The largest relative excess σ̃/σ̃_y − 1 of the von Mises stress over the yield stress at the
/// integration points of plastic materials (the admissibility of a state; −inf: no plastic
/// material).
struct YieldExcess : PointLargest {
  /// The slack of the check σ̃ ≤ σ̃_y·(1 + slack): round-off of the curves' own evaluation, far
  /// below any tolerance a step converges to.
  static constexpr double slack = 1e-6;
};

struct StepReport {
  int step = 0;  ///< 1-based count of converged steps
  double time = 0;
  int iterations = 0;
  double residual = 0;     ///< ‖F_ext − F_int‖ on the free dofs, relative
  double delta_sigma = 0;  ///< the scheme's Δ^σ of the last iteration (0 without plasticity)
  double delta_eps = 0;    ///< the scheme's Δ^ε of the last iteration
  int factorizations = 0;  ///< matrix factorizations in this step (cut-back attempts included)
  int plastic_points = 0;  ///< integration points that flowed plastically in this step
  YieldExcess yield_excess;  ///< of the committed state
  PointLargest point_von_mises;  ///< the committed state's largest von Mises stress at a point
  bool last = false;       ///< the final step of the analysis
  /// The step's fields are written (every output.every-th step and the last): the recovered
  /// fields then hold the cells' values too.
  bool write_fields = false;
};

struct Timings {
  double assembly = 0, factorization = 0, solve = 0, material = 0, output = 0;
  double contact = 0;  ///< contact search and state updates
  double heat = 0;     ///< the heat analysis (all of it: assembly, factorization, solves)
};

struct RecoveredFields;  // solve/recovery.hpp

/// The measures of one iterate of a step (output.iterations).
struct IterateReport {
  int attempt = 0;  ///< 1-based count of the steps attempted (cut-backs and failures included)
  double time = 0;  ///< the step's end time
  int iteration = 0;
  double residual = 0, delta_sigma = 0, delta_eps = 0;
  int plastic_points = 0;
};

class StepObserver {
 public:
  virtual ~StepObserver() = default;
  /// Whether iterate_done is wanted (output.iterations).
  virtual bool wants_iterates() const { return false; }
  /// Called on every rank after each iterate of a step is evaluated and measured, with the
  /// iterate's state.
  virtual void iterate_done(const IterateReport& report, const State& trial) {
    (void)report;
    (void)trial;
  }
  /// Called on every rank after every converged step with the committed state (this rank's
  /// integration points) and the point values recovered to the nodes, and to the cells when
  /// report.write_fields (recover_fields, solve/recovery.hpp, says what each rank gets).
  virtual void step_done(const StepReport& report, const State& state,
                         const RecoveredFields& fields) = 0;
};

}  // namespace hencky
