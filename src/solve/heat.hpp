#pragma once
// Heat conduction on the mechanical mesh: the case's heat section (docs/heat.md), solved step
// by step ahead of the mechanical steps that take its temperatures (temperature: {from: heat}),
// the sequentially coupled analysis of CalculiX's *HEAT TRANSFER or code_aster's THER_NON_LINE
// followed by a stress analysis.
//
// The weak form on the nodal temperatures T, with G the residual of the step from t0 to t1:
//   transient: G(T) = ∫ (H(T) − H(T0)) N dV / Δt + θ R(T, t1) + (1 − θ) R(T0, t0)
//   steady:    G(T) = R(T, t1)
//   R(T, t) = ∫ k(T) ∇N·∇T dV − ∫ Q(x, t, T) N dV − ∫ q_in(T, t) N dA
// with H(T) = ∫ ρc dT the enthalpy per volume (so that the stored heat is exact for any ρ(T),
// c(T)) and q_in the heat flux into the body of the flux, convection h (T∞ − T) and radiation
// εσ ((T∞ − T_0)⁴ − (T − T_0)⁴) conditions (T_0 the absolute zero); a nodal_flux condition's
// heat flow goes into R at its nodes directly. Newton's matrix is dG/dT
// without the term k'(T) N ∇T·∇N, which is not symmetric (the linear systems are), and without
// the −dQ/dT N N of a source that grows with T (which would make it indefinite): this symmetric
// part is factorized. Where those terms exist (k(T) a table, Q of T), the Newton step solves
// the whole dG/dT by GMRES with the factorized part as its (right) preconditioner, applying
// dG/dT cell by cell without assembling it: Newton stays Newton (quadratic convergence), and
// each step costs a few extra passes over the cells.
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/model.hpp"

namespace hencky {

/// The heat analysis cannot reach a time: its Newton iteration failed at every cut-back.
class HeatDivergence : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// ρc(T) and the enthalpy per volume H(T) = ∫_{T_ref}^{T} ρ(τ)c(τ) dτ of a material: exact for
/// tables (linear between their temperatures, constant beyond), whose product is quadratic
/// between the union of their temperatures (two-point Gauss).
class HeatCapacity {
 public:
  HeatCapacity() = default;
  HeatCapacity(const PropertyTable& density, const PropertyTable& specific_heat, double T_ref);
  double rho_c(double T) const { return (*rho_)(T) * (*c_)(T); }
  double enthalpy(double T) const;

 private:
  double integral(double a, double b) const;  ///< ∫_a^b ρc dT, a and b in one piece
  const PropertyTable* rho_ = nullptr;
  const PropertyTable* c_ = nullptr;
  std::vector<double> T_;  ///< the pieces' ends: the tables' temperatures, and T_ref
  std::vector<double> H_;  ///< H at T_
};

/// The heat solution at one time.
struct HeatSnapshot {
  double time = 0;
  std::vector<double> T;  ///< nodal temperatures
  /// Per heat.boundary entry, the heat into the body in W over the step that ended here:
  /// θ q(t1) + (1 − θ) q(t0) (exactly what the step's heat balance holds), for a temperature
  /// condition the reaction of its nodes.
  std::vector<double> flow;
  std::vector<double> flow_now;  ///< the natural conditions' q(time) (the next step's q(t0))
  std::vector<double> energy;    ///< per entry, the heat brought in since t = 0 (J; transient)
};

/// What the heat analysis carries from one mechanical step to the next (HeatSolver::memory):
/// its solutions from the last committed time on, and its counts. Nodal: whole on every rank.
struct HeatMemory {
  std::deque<HeatSnapshot> snapshots;  ///< empty: the analysis has not started
  std::vector<double> R_last, S_last;  ///< R and its scale at the newest snapshot
  double committed = 0;
  int steps = 0, iterations = 0, gmres_iterations = 0;
};

/// The case's expressions of the heat section, one copy per thread (solve/heat_terms.hpp).
struct HeatExpressions;

class HeatSolver {
 public:
  /// The linear system of the temperature dofs (the same back end as the mechanical one).
  using SystemFactory =
      std::function<std::unique_ptr<LinearSystem>(const Assembler&, const DofMap&)>;

  /// Throws InputError when the conditions do not determine a steady temperature.
  /// Collective.
  HeatSolver(const Model& model, const SystemFactory& make_system, Log& log);
  ~HeatSolver();

  /// The nodal temperatures and the heat flows of the heat.boundary entries at time t, no
  /// earlier than the last committed() time: the heat analysis is advanced to the first of
  /// its step times at or after t, and interpolated linearly in time between the two that
  /// bracket t. A transient's flows are the mean over [last committed time, t] (the heat
  /// brought in over that time divided by it: exact whatever the heat steps); a steady one's
  /// are those at t. The first call sets the solution at t = 0 up: the initial temperature
  /// (transient) or the steady solution at t = 0. Throws HeatDivergence, and InputError for a
  /// value of the case that cannot be used (a negative film coefficient). Collective.
  void at(double t, std::vector<double>& T, std::vector<double>& flow);
  /// The mechanical analysis has converged at time t: no earlier time will be asked for.
  void committed(double t);

  HeatMemory memory() const;
  /// Continues from the memory of the run that wrote a checkpoint (a restart).
  void resume(HeatMemory mem);

  int steps() const { return mem_.steps; }
  int iterations() const { return mem_.iterations; }
  /// GMRES iterations of the Newton steps with k(T) or Q(T) (0 when there are none).
  int gmres_iterations() const { return mem_.gmres_iterations; }
  double seconds() const { return seconds_; }
  const LinearSolverStats& stats() const { return system_->stats(); }

 private:
  struct Evaluation;
  void start();
  /// G, its scale and (when `matrix`) the system matrix at T for the step from `from` to t1.
  void evaluate(const std::vector<double>& T, const HeatSnapshot& from, double t1, bool matrix,
                Evaluation& ev);
  /// One Newton solve to t1 from `from`; false when it does not converge (`why` says why).
  bool solve(const HeatSnapshot& from, double t1, HeatSnapshot& to, std::string& why);
  /// The converged step's flows, reactions and energies into `to`, from the residual at its
  /// temperatures.
  void step_flows(const HeatSnapshot& from, const Evaluation& ev, HeatSnapshot& to) const;
  /// Takes the next step (with cut-backs) toward `target`.
  void advance(double target);
  void natural_flows(const std::vector<double>& T, double t, std::vector<double>& q) const;
  /// The heat flow into node `node` of nodal_flux entry `boundary` at time t (W).
  double nodal_flow(int boundary, int node, double t) const;
  /// The snapshots' values at t (linear between the two that bracket it); T may be null.
  void interpolate(double t, std::vector<double>* T, std::vector<double>& flow,
                   std::vector<double>& energy) const;
  /// out = dG/dT v at T (v and out per node, v zero at prescribed nodes). Collective.
  void jacobian_times(const std::vector<double>& T, const HeatSnapshot& from, double t1,
                      const std::vector<double>& v, std::vector<double>& out);
  /// The Newton step x of dG/dT x = b (free dofs) by right-preconditioned GMRES
  /// (linalg/gmres.hpp), from x = P⁻¹ b (P the factorized symmetric part), to the relative
  /// residual rtol; false when it stalls.
  bool full_newton_step(const std::vector<double>& T, const HeatSnapshot& from, double t1,
                        const std::vector<double>& b, std::vector<double>& x, double rtol);
  void fixed_temperatures(double t, std::vector<double>& T) const;

  const Model& model_;
  const HeatSpec& spec_;
  Log& log_;
  std::unique_ptr<LinearSystem> system_;
  std::vector<HeatCapacity> capacity_;        ///< per material (transient)
  std::vector<HeatExpressions> expressions_;  ///< one copy per thread
  /// The snapshots (times increasing, the last the newest), R at the newest, the last
  /// committed time and the counts: what a checkpoint keeps (memory(), resume()).
  HeatMemory mem_;
  std::size_t next_target_ = 0;  ///< own steps (heat.times): the next one
  bool linear_ = false;          ///< the matrix depends on neither T nor t (only on Δt)
  bool nonsymmetric_ = false;    ///< dG/dT has terms the factorized matrix leaves out
  double theta_ = 1.0;           ///< θ of the step being taken (1 in the start of θ < 1)
  int last_iterations_ = 0;      ///< of the last converged solve, for its log line
  double last_residual_ = 0;
  double factored_dt_ = -1;  ///< Δt(2 − θ) of the factorized matrix when linear_ (0: steady)
  double seconds_ = 0;
};

/// The heat flux q = −k(T) ∇T at the nodes, 3 per node: each cell's at its nodes, averaged
/// over the cells around a node (over all ranks: collective on several ranks).
std::vector<double> nodal_heat_flux(const Model& model, const std::vector<double>& T);

}  // namespace hencky
