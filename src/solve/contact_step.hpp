#pragma once
// The contact part of a step (report section 3) for the equilibrium iteration
// (equilibrium.cpp): the initial states (3.1), the support's forces in the residual and G in the
// matrix (3.2)/(3.3), the force and state update after each solve (3.4)/(3.5) and step 4, the κ
// strategy, and the checks that end a step: no node changed its state, the gaps of the nodes in
// contact are within the allowed penetration, and the contact set does not oscillate.
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "solve/analysis.hpp"

namespace hencky {

/// How the contact stands after an update.
struct ContactProgress {
  bool set_changed = false;  ///< some node changed Contact or Separation in this update
  bool kappa_raised = false; ///< the κ strategy raised some node's κ
  double worst_gap = 0;      ///< largest |gap| / allowed over the nodes in contact (≤ 1: done)
  double max_penetration = 0;  ///< largest penetration (−gap) of any node, in length units
  int in_contact = 0;          ///< nodes in contact, over all surfaces
  int released = 0;            ///< nodes in contact at t that this update released
  bool converged() const { return !set_changed && worst_gap <= 1; }
};

class ContactStep {
 public:
  /// `max_flips`: the changes between contact and no contact a node may make in a step
  /// before update() calls the set oscillating.
  explicit ContactStep(const Model& m, int max_flips = default_max_flips);
  bool active() const { return !m_->contacts().empty(); }

  /// The states at t = 0: nodes that touch a surface (to round-off, or within the allowed
  /// penetration) start in Contact with zero force, so that a body resting on a support is
  /// held from the first solve; all others are free.
  void initial(State& s) const;
  /// (3.1): the iteration starts from the committed states, with the contact points moved
  /// with their surfaces from t to t + Δt.
  void begin(const State& c, State& trial);
  /// The support's forces at the current iterate into trial.f_contact (3 per mesh node).
  void forces(State& trial) const;
  /// Adds G of every node in contact into the upper-triangle matrix values and remembers
  /// what it added (matrix_stale compares against it).
  void add_matrix(const State& trial, std::span<double> values);
  /// The same through add(a, b, block): the 3x3 block coupling mesh nodes a (rows) and b
  /// (columns), for every ordered pair of the point's nodes (the PETSc back end).
  void add_matrix(const State& trial, const std::function<void(int, int, const Mat3&)>& add);
  /// The matrix last assembled no longer holds the G of the current states: a node entered
  /// or left contact, its κ changed, or its normal turned by more than 1e-3 rad. On a
  /// distributed mesh, on any rank (collective then, as update() and summary() are).
  bool matrix_stale(const State& trial) const;
  /// Report steps 3-4 for every node after a solve, then the κ strategy. Throws SolveError
  /// when the contact set oscillates (a node changed state more than max_flips times in the
  /// step): the step is then cut back.
  ContactProgress update(const State& c, State& trial);
  /// At a converged iterate: releases every node in contact on which the surface pulls with
  /// more than `limit` (the force of contact_force at the iterate, −F·n > limit), as the
  /// update's branch `released` does for a node outside the surface; returns their number over
  /// the whole model (collective on a distributed mesh).
  int release_pulling(const State& c, State& trial, double limit);
  /// The augmented state of every node as one number, c = F·n + κ r*·n: the force the solve
  /// puts on a node in contact at r is (c − κ r·n) n, linear in r for a fixed c (0 for the
  /// nodes out of contact). `weight` (when given): 1/κ at the nodes in contact, else 0.
  void augmented_offsets(const State& s, std::vector<double>& c,
                         std::vector<double>* weight = nullptr) const;
  /// Sets c at the nodes in contact (their F·n follows; r* and n stay).
  void set_augmented_offsets(State& s, std::span<const double> c) const;
  /// The progress of the last update (or of begin(): all quiet).
  const ContactProgress& progress() const { return progress_; }
  /// Why the contact kept a step from converging ("" when it did not): for the message of a
  /// failed step.
  std::string diagnosis() const;
  /// One line per surface for the log of a converged step.
  std::string summary(const State& s) const;

  /// The states whose G is in the matrix (empty before the first assembly).
  std::vector<std::vector<ContactNode>> assembled() const {
    return assembled_any_ ? assembled_ : std::vector<std::vector<ContactNode>>();
  }

  static constexpr int default_max_flips = 6;
  int max_flips() const { return max_flips_; }

 private:
  int max_flips_;
  Vec3 position(int body, int i, const std::vector<double>& u) const;

  /// Point i of surface b counts here: on a distributed mesh each point is counted, and adds
  /// its forces and matrix, on the rank that owns its node alone (its other copies follow the
  /// same states); elsewhere every point counts on every rank.
  bool counts(std::size_t b, std::size_t i) const { return owned_.empty() || owned_[b][i]; }

  const Model* m_;
  bool distributed_ = false;
  std::vector<std::vector<char>> owned_;  ///< per surface and point, on a distributed mesh
  std::vector<double> k_min_, k_max_;     ///< per surface: the points' stiffness, over the ranks
  std::vector<Vec3> m0_, m1_;  ///< translation of each surface at t and t + Δt
  // Per surface and point, during a step:
  std::vector<std::vector<Vec3>> r_t_;          ///< the position at t (fixed in the step)
  std::vector<std::vector<int>> flips_;         ///< changes of Contact
  std::vector<std::vector<double>> prev_gap_;   ///< |gap| at the previous update (in contact)
  std::vector<std::vector<ContactNode>> assembled_;  ///< the states whose G is in the matrix
  bool assembled_any_ = false;
  ContactProgress progress_;
};

}  // namespace hencky
