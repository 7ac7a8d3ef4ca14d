#pragma once
// The evaluation of an iterate of a load step (report section 2): the step's set-up and its
// equilibrium target (2.29)-(2.30), the points' pass and the contact's update at an iterate,
// and the residual the next solve corrects. Equilibrium (equilibrium.hpp) orders the stages;
// this computes them.
#include <vector>

#include "core/log.hpp"
#include "solve/contact_step.hpp"
#include "solve/heat.hpp"
#include "solve/point_pass.hpp"
#include "solve/state.hpp"

namespace hencky {

/// An evaluated iterate: what its point pass found and its squared residual norms.
struct Evaluation {
  PointPassResult points;
  double r2 = 0;        ///< ‖target + F_contact − F_int‖² on the free dofs (rhs() holds it)
  double r_loads2 = 0;  ///< the same without the supports' forces
};

class IterateEvaluator {
 public:
  /// `only`: this rank's cells (nullptr: every cell); `heat`: the heat analysis whose
  /// temperatures the steps take, else none; `max_flips`: the contact's flip limit.
  IterateEvaluator(const Model& m, const std::vector<char>* only, const Scheme& scheme,
                   int max_flips, Log& log, Timings& timings, HeatSolver* heat);

  /// The step's loads, temperatures and prescribed displacements at t1, the points' and the
  /// contact's set-up, and the equilibrium target (2.29)-(2.30).
  void begin(const State& c, double t1, State& trial);
  /// A heat analysis alone (HeatSpec::only): the step to t1 is its temperatures, at the nodes
  /// and the points; the rest of `trial` is c's.
  void temperatures_only(const State& c, double t1, State& trial);
  /// The iterate trial.u: points and internal forces, then (with `update_contact`, after a
  /// solve) the contact's steps 3-4, then the residual. `mode`: how the points of plastic
  /// materials are evaluated (PointPass::update).
  Evaluation evaluate(const State& c, State& trial, bool update_contact,
                      PointMode mode = PointMode::law);
  /// The contact states updated at the evaluated iterate (with contact), then its residual
  /// (what evaluate does after the points with `update_contact`).
  void update_contact(const State& c, State& trial, Evaluation& ev);
  /// rhs() = target + F_contact − F_int on the free dofs for the evaluated iterate (the
  /// supports' forces computed here, into trial.f_contact); returns its squared norm, and in
  /// *loads2 (when given) that of target − F_int, the residual without the supports.
  double residual_vector(State& trial, double* loads2 = nullptr);
  /// ‖F_ext + F_contact − F_int‖ of a state on the free dofs, over the whole model.
  double equilibrium_defect(const State& s) const;

  /// ‖u − u_before‖/‖u − u(t)‖ of the iterate u = trial.u over the whole model: its last
  /// correction against the step's increment (0 for no increment).
  double correction_ratio(const State& c, const State& trial,
                          const std::vector<double>& u_before) const;
  /// ‖v‖ of a complete nodal vector (3 per node) over the whole model.
  double norm(const std::vector<double>& v) const;
  /// The force scale of the step, fixed at its start: the loads, the internal forces before
  /// and after the first iterate (reactions included), and its residual (which carries thermal
  /// and prescribed-displacement loading). It vanishes in a step whose start and target have no
  /// load and no stress: free expansion, or unloading to zero (then history_force holds the
  /// scale).
  double step_force(const State& c, const State& trial, const Evaluation& ev) const;
  /// The force scale of the history: the time average of the steps' force scales over the
  /// converged steps (as Abaqus/Standard's time-averaged force, Abaqus Analysis User's Guide
  /// 7.2.3). A step whose own forces have gone to round-off, as when the load has been removed
  /// and the body is free of stress, measures its residual against the forces the analysis has
  /// carried, which cannot vanish once a load was applied.
  static double history_force(const State& c) {
    return c.time > 0 ? c.force_integral / c.time : 0.0;  // the analysis starts at t = 0
  }

  const Model& model() const { return m_; }
  /// The leading entries of a free-dof vector that are this rank's own.
  int own_free() const { return own_free_; }
  PointPass& points() { return points_; }
  const PointPass& points() const { return points_; }
  ContactStep& contact() { return contact_; }
  const ContactStep& contact() const { return contact_; }
  /// The nodes' coordinates the step is written on: the mesh's, or X + u(t) under `updated`.
  const std::vector<Vec3>& x() const { return x_; }
  /// The residual of the last evaluated iterate on the free dofs (the next solve's right side).
  const std::vector<double>& rhs() const { return rhs_; }
  /// A cell with a negative variable-stiffness secant in the last point pass, or -1.
  int negative_secant_cell() const { return negative_secant_cell_; }

 private:
  double correction(double t1) const;
  void report_defect(const State& c) const;

  const Model& m_;
  Log& log_;
  Timings& timings_;
  HeatSolver* heat_;
  PointPass points_;
  ContactStep contact_;
  const NodalLayout& layout_;
  std::size_t own_dofs_;  ///< the leading entries of a nodal vector that are this rank's own
  int own_free_;          ///< the same of a free-dof vector
  bool updated_;          ///< solver.geometry: updated
  std::vector<Vec3> x_;
  std::vector<double> loads_at_t_, forces_at_t_;  ///< P and ∫Bᵀσ(t) on x_ (updated)
  std::vector<double> target_, rhs_;
  int negative_secant_cell_ = -1;
};

}  // namespace hencky
