#pragma once
// The equilibrium iteration of one load step (report section 2): the target (2.29)-(2.30),
// the evaluation of an iterate (points, contact, residual, measures), the convergence test,
// and the advance to the next iterate (matrix when it changed, solve, acceleration). The step
// control (step_control.cpp) decides which steps to take; this decides whether one converges.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/anderson.hpp"
#include "solve/contact_step.hpp"
#include "solve/heat.hpp"
#include "solve/point_pass.hpp"
#include "solve/state.hpp"

namespace hencky {

/// How a step ended, or how far it got: the figures of its last iterate.
struct StepOutcome {
  int iterations = 0;
  double residual = 0;     ///< relative; at convergence the true equilibrium defect
  double delta_sigma = 0;  ///< the scheme's Δ^σ (0 without plasticity)
  double delta_eps = 0;
  int plastic_points = 0;
};

class Equilibrium {
 public:
  /// `heat`: the heat analysis whose temperatures the steps take (temperature: {from: heat}),
  /// else none.
  Equilibrium(const Model& m, LinearSystem& system, Log& log, Timings& timings,
              HeatSolver* heat = nullptr);

  /// The initial state: undeformed, stress-free, at T_ref, no load.
  State initial_state() const;

  /// One step from `c` (committed at c.time) to time t1. Returns true when it converged and
  /// fills `trial`; `out` describes the last iterate either way (also when it throws).
  /// Throws SolveError (and LinearSystemError) when the step cannot go on.
  bool step(const State& c, double t1, State& trial, StepOutcome& out);

  int factorizations() const { return factorizations_; }
  /// What the next step takes from the steps before it besides the State.
  EquilibriumMemory memory() const;
  /// Continues after a restart from `c` with the memory `mem` of the run that wrote it: the
  /// same matrix is assembled and factorized again. Collective.
  void resume(const State& c, EquilibriumMemory mem);
  /// Warnings after a converged step (curves left, temperatures outside tables). Collective.
  void check_curves(const State& s) const { points_.check_curves(s, log_); }
  /// Why the contact kept a failed step from converging (empty without contact).
  std::string contact_diagnosis() const { return contact_.diagnosis(); }
  /// The contact line of a converged step's log entry (empty without contact).
  std::string contact_summary(const State& s) const {
    return contact_.active() ? contact_.summary(s) : std::string();
  }

 private:
  /// An evaluated iterate: what its point pass found and its squared residual norms.
  struct Evaluation {
    PointPassResult points;
    double r2 = 0;        ///< ‖target + F_contact − F_int‖² on the free dofs (rhs_ holds it)
    double r_loads2 = 0;  ///< the same without the supports' forces
  };

  void begin(const State& c, double t1, State& trial);
  double correction(double t1) const;
  void report_defect(const State& c) const;
  double norm(const std::vector<double>& v) const;
  double step_force(const State& c, const State& trial, const Evaluation& ev) const;
  double history_force(const State& c) const;
  Evaluation evaluate(const State& c, State& trial, bool update_contact, bool elastic = false);
  void update_contact_states(const State& c, State& trial);
  void require_strain_form(const Evaluation& ev) const;
  Evaluation predict(const State& c, State& trial, const Evaluation& at_start, double scale,
                     bool& extrapolated);
  Evaluation begin_again(const State& c, State& trial, const std::vector<double>& u_start);
  void report(const StepOutcome& out) const;
  bool converged(const StepOutcome& out) const;
  void accept(const State& c, State& trial, double scale, StepOutcome& out);
  bool released_pulling(const State& c, State& trial, Evaluation& ev, double scale,
                        StepOutcome& out);
  void advance(const State& c, State& trial, const Evaluation& ev, int iteration,
               double residual, double& previous_residual);
  void line_search(const State& c, State& trial);
  void mix(State& trial);
  double strain_state_change(const State& trial);
  double residual_vector(State& trial, double* loads2 = nullptr);
  double equilibrium_defect(const State& s) const;
  void remember_increment(const State& c, const State& trial);
  void assemble_and_factorize(const State& c, const State& trial, bool new_elements);
  void factorize();

  const Model& m_;
  LinearSystem& system_;
  HeatSolver* heat_;
  Log& log_;
  Timings& timings_;
  const std::vector<char>* only_;  ///< this rank's cells, on more than one rank
  bool plastic_;
  std::unique_ptr<Scheme> scheme_;
  PointPass points_;
  ContactStep contact_;
  const NodalLayout& layout_;
  std::size_t own_dofs_;  ///< the leading entries of a nodal vector that are this rank's own
  int own_free_;          ///< the same of a free-dof vector
  bool matrix_changes_with_temperature_ = false;
  // solver.geometry: updated; the nodes' coordinates the step is written on: the mesh's, or
  // X + u(t) under `updated` (set by begin)
  bool updated_ = false;
  std::vector<Vec3> x_;
  std::vector<double> loads_at_t_, forces_at_t_;  ///< P and ∫Bᵀσ(t) on x_ (updated)
  bool factorized_ = false;
  std::vector<Tangent> assembled_tangents_;  ///< the points' matrices in the elements' part
  bool options_checked_ = false;  ///< unused options of the back end were reported
  int factorizations_ = 0;
  double model_size_ = 0;          ///< diagonal of the mesh's bounding box
  int negative_secant_cell_ = -1;  ///< of the last point pass, for factorize's message
  std::vector<double> target_, rhs_, delta_;
  // newton's predictor (solver.predictor): the last converged increment of the free unknowns
  // and its Δt
  bool extrapolate_ = false;
  std::vector<double> last_du_;
  double last_dt_ = 0;
  bool mix_ = false;       ///< solver.acceleration resolved: Anderson mixing of the iterates
  bool elastic_start_ = true;  ///< the first solve of a step that yields points is elastic
  int max_iterations_ = 50;  ///< solver.max_iterations resolved
  /// The step's iterates' worst measure over the tolerance (converging_on's history).
  std::vector<double> distances_;
  /// At or past the iteration limit: true while the step may go on (its measures falling
  /// steadily enough to meet the tolerance before twice the limit).
  bool converging_on(const StepOutcome& out) const;
  // solver.line_search resolved; the line search's evaluation of u + δ when it took δ whole
  // (the next iterate's, without contact), and the iterate it searched from
  bool line_search_ = false;
  std::optional<Evaluation> searched_;
  std::vector<double> u_before_;
  Anderson anderson_;  ///< 8 columns for the initial strains, 5 otherwise (constructor)
  // mix(): the iterate, its plain correction and the rows' weights; the initial-strain
  // schemes' Δε^0 the current iterate was evaluated with and the points' plain update of it
  std::vector<double> mix_x_, mix_f_, mix_weights_, lambda0_in_, lambda0_out_, point_weights_;
  // with contact, the nodes' augmented state c (ContactStep::augmented_offsets) likewise
  std::vector<double> contact_in_, contact_out_, contact_weights_;
  // The initial-strain schemes: the weighted square of the change of their state that the last
  // iterate kept asked for (strain_state_change), what the safeguard compares the next with.
  double last_change_ = 0;
  // The plain iterate the last mixed one replaced (its displacements, contact and points'
  // memory), taken instead when the mixed one doubled the residual.
  bool mixed_last_ = false, restart_next_ = false;
  // The iteration the step's points started from: 0, or 1 when it began again (begin_again).
  int first_iteration_ = 0;
  std::vector<double> plain_u_;
  std::vector<std::vector<ContactNode>> plain_contact_;
  // The initial-strain schemes' held plastic set (hold, move_holds): the iteration of the
  // step from which it is held, the iterates in a row with the same number of broken holds
  // after which these move, whether it may be held (this step), is, and its moves so far; the
  // number of broken holds of the last iterate (−1: none since the last hold or move) and in
  // how many iterates in a row it was that number.
  static constexpr int hold_from = 20, max_hold_moves = 10, settled_breaks = 3;
  bool hold_set_ = false, holding_ = false;
  int hold_moves_ = 0, last_broken_ = -1, same_broken_ = 0;
  void hold(int plastic_points);
  void move_holds(int broken, bool converged);
  void new_held_set();
};

}  // namespace hencky
