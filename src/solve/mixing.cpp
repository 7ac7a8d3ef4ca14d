#include "solve/mixing.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "parallel/mpi.hpp"

namespace hencky {

Mixing::Mixing(bool enabled, int depth, bool strains, IterateEvaluator& iterate,
               const std::vector<char>* only)
    : iterate_(iterate), only_(only), enabled_(enabled), strains_(strains), anderson_(depth) {}

void Mixing::start_step() {
  anderson_.reset();
  mixed_last_ = restart_next_ = false;
  last_change_ = INFINITY;
  previous_residual_ = INFINITY;
}

/// Whether this iterate made things worse than the one before. The residual doubled, or for
/// the initial-strain schemes the change of their iterated state (Δε^0, and the contact
/// nodes' c) that its evaluation asks for, in the norm Anderson's least squares minimizes,
/// grew tenfold. The residual is no merit function for them: a mixed iterate that settles
/// the slow plastic strains along Z raised it up to twentyfold for one iteration while their
/// change fell tenfold, and the iterations after it converged; dropping such iterates kept
/// the ball indentation's history at one column (t = 0.25 -> 0.5: 614 iterations; with the
/// change doubled as the criterion 305, tenfold 177, with no fallback at all 178). The
/// fallback is still what stops a mixed iterate that throws the points off their branch
/// (the multilinear cube below).
bool Mixing::fell_back(State& trial, int iteration, double residual, Log& log) {
  if (!enabled_) return false;
  double change = 0;
  if (strains_ && iteration > 0) change = strain_state_change(trial);
  worse_ =
      strains_ ? iteration > 0 && change > 100 * last_change_ : residual > 2 * previous_residual_;
  if (mixed_last_ && worse_) {
    // Safeguarded mixing: a mixed iterate that made things worse is dropped for the plain one
    // it replaced, and the history starts again there (as Peng et al., "Anderson
    // acceleration for geometry optimization and physics simulation", ACM TOG 37(4), 2018,
    // fall back to the plain step when the mixed one does not decrease their energy). The next
    // iteration evaluates it; nothing is solved in this one. Without it, a mixed λ0 that put
    // every point of a multilinear cube below its yield stress made the plain update return
    // to the step's start: a cycle of three iterations until the step failed.
    log.detail(
        "  the mixed iterate {}: back to the plain one",
        strains_ ? "raised the change of the initial strains tenfold" : "doubled the residual");
    trial.u = plain_u_;
    trial.contact = plain_contact_;
    iterate_.points().restore_memory();
    if (strains_) {  // the plain iterate's state, which its evaluation's change is measured from
      iterate_.points().initial_strains(points_.in);
      if (iterate_.contact().active()) iterate_.contact().augmented_offsets(trial, contact_.in);
    }
    mixed_last_ = false;
    restart_next_ = true;  // the history starts again at the plain iterate
    return true;
  }
  if (strains_ && iteration > 0) last_change_ = change;
  return false;
}

void Mixing::mix_correction(State& trial, std::vector<double>& delta, int iteration,
                            double residual, bool refactored) {
  if (!enabled_) return;
  const auto& dofs = iterate_.model().dofs();
  const ContactStep& contact = iterate_.contact();
  // A new matrix is a new fixed-point map, and so is a new contact set or a raised κ; a step
  // that doubled the residual left the region where the history describes it: start the
  // history again from here.
  const bool contact_moved =
      contact.active() && (contact.progress().set_changed || contact.progress().kappa_raised);
  const bool restart = iteration == 0 || refactored || contact_moved || restart_next_ || worse_;
  restart_next_ = false;
  if (restart) anderson_.reset();
  previous_residual_ = residual;
  // The initial-strain schemes' displacement follows their Δε^0 only from the first solve
  // with the matrix on: the start of a step (u(t), the new load not yet applied) and the
  // iterate before a new matrix do not. Their plain update is the history's first entry.
  // After a restart the history holds nothing: the step is the plain one.
  mixed_last_ = !restart;
  if (mixed_last_) {
    plain_u_ = trial.u;
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) plain_u_[i] += delta[k];
    plain_contact_ = trial.contact;
    iterate_.points().save_memory();
  }
  if (strains_ && restart) {
    iterate_.points().initial_strains(points_.in);
    if (contact.active()) contact.augmented_offsets(trial, contact_.in);
  } else {
    mix(trial, delta);
  }
}

/// The initial-strain schemes: the points' plain update of Δε^0 and the contact nodes' c
/// (into the blocks' `out`) against the state the iterate was evaluated with (`in`), with the
/// rows' weights of Anderson's least squares (the contact's shared out over the ranks); returns
/// the weighted square of the change, over all ranks.
double Mixing::strain_state_change(const State& trial) {
  const NodalLayout& layout = iterate_.model().layout();
  iterate_.points().initial_strains(points_.out);
  iterate_.points().plastic_point_weights(points_.weights);
  double sum = 0;
  for (std::size_t j = 0; j < points_.out.size(); ++j) {
    const double d = points_.out[j] - points_.in[j];
    sum += points_.weights[j] * d * d;
  }
  contact_.out.clear();
  if (iterate_.contact().active()) {
    iterate_.contact().augmented_offsets(trial, contact_.out, &contact_.weights);
    // With the whole mesh every rank holds every contact node: its rows, summed over the
    // ranks, count once. (A distributed mesh's contact weights are its owners' alone.)
    const double share = only_ ? 1.0 / par::size() : 1.0;
    for (std::size_t j = 0; j < contact_.out.size(); ++j) {
      contact_.weights[j] *= share;
      const double d = contact_.out[j] - contact_.in[j];
      sum += contact_.weights[j] * d * d;
    }
  }
  // The points are each rank's own.
  if (only_ || layout.kind() == NodalLayout::Kind::distributed)
    par::sum_in_place(std::span<double>(&sum, 1));
  // Every rank takes the same decisions with it: root's figure.
  if (layout.shared()) par::broadcast(std::span<double>(&sum, 1));
  return sum;
}

/// Anderson's mixing of this iteration: the plain correction delta (and, for the
/// initial-strain schemes, the points' plain update of Δε^0) replaced by the mixed one.
/// The initial-strain schemes iterate on Δε^0, and the displacement follows it: after one
/// solve with the scheme's fixed matrix, u + δ is the displacement of the plain update of Δε^0
/// exactly (the stress law is linear in Δε for fixed Δε^0), so the mixed displacement is the
/// same combination of those displacements as the mixed Δε^0 is of the plain updates. The
/// least squares then weighs only Δε^0 (by the points' volumes and moduli) and the contact's
/// c; the displacements weigh 0.
void Mixing::mix(State& trial, std::vector<double>& delta) {
  const auto& dofs = iterate_.model().dofs();
  const NodalLayout& layout = iterate_.model().layout();
  const bool contact = strains_ && iterate_.contact().active();
  const std::size_t n_u = dofs.n_free;
  // (fell_back gathered the points' and nodes' plain update and their weights)
  const std::size_t n_l = strains_ ? points_.out.size() : 0;
  const std::size_t n_c = contact ? contact_.out.size() : 0;
  const std::size_t n = n_u + n_l + n_c;
  // The rows' weights: 1 for displacements iterated themselves, 0 for those that follow the
  // mixed state; volume·2G or G for Δε^0 and 1/κ for a contact node's c, so that each weighted
  // square is an energy.
  rows_w_.assign(n, strains_ ? 0.0 : 1.0);
  if (strains_) std::copy(points_.weights.begin(), points_.weights.end(), rows_w_.begin() + n_u);
  // A distributed mesh: a ghost's rows are its owner's (weight 0 here).
  const bool distributed = layout.kind() == NodalLayout::Kind::distributed;
  if (distributed) std::fill(rows_w_.begin() + iterate_.own_free(), rows_w_.begin() + n_u, 0.0);
  for (std::size_t j = 0; j < n_c; ++j) rows_w_[n_u + n_l + j] = contact_.weights[j];
  rows_x_.resize(n);
  rows_f_.resize(n);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) rows_x_[k] = trial.u[i];
  std::copy(delta.begin(), delta.end(), rows_f_.begin());
  for (std::size_t j = 0; j < n_l; ++j) {
    rows_x_[n_u + j] = points_.in[j];
    rows_f_[n_u + j] = points_.out[j] - points_.in[j];
  }
  for (std::size_t j = 0; j < n_c; ++j) {
    rows_x_[n_u + n_l + j] = contact_.in[j];
    rows_f_[n_u + n_l + j] = contact_.out[j] - contact_.in[j];
  }
  // The displacements are whole on every rank, or a distributed mesh's own rows on each; the
  // points are each rank's own.
  std::function<void(std::span<double>)> reduce;
  if ((strains_ && only_) || distributed)
    reduce = [](std::span<double> v) { par::sum_in_place(v); };
  anderson_.accelerate(rows_x_, rows_f_, rows_w_, reduce);
  std::copy(rows_f_.begin(), rows_f_.begin() + n_u, delta.begin());
  if (strains_) {
    for (std::size_t j = 0; j < n_l; ++j) points_.in[j] = rows_x_[n_u + j] + rows_f_[n_u + j];
    iterate_.points().set_initial_strains(points_.in);
  }
  if (contact) {
    for (std::size_t j = 0; j < n_c; ++j)
      contact_.in[j] = rows_x_[n_u + n_l + j] + rows_f_[n_u + n_l + j];
    iterate_.contact().set_augmented_offsets(trial, contact_.in);
  }
}

}  // namespace hencky
