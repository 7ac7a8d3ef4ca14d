#pragma once
// The integration-point values of a converged step brought to the nodes and the cells, for
// the outputs (fields, probes). On several MPI ranks each rank holds only its own cells'
// points (Model::hold_points): each computes its cells' share and root receives the sums.
#include <vector>

#include "solve/analysis.hpp"

namespace hencky {

struct RecoveredFields {
  /// Per node: each cell extrapolates its point values to its nodes
  /// (reference_table().extrapolation), a node averages over all its cells.
  std::vector<Voigt> nodal_stress;
  std::vector<Voigt> nodal_plastic_strain;  ///< engineering shears; empty without plasticity
  std::vector<double> nodal_eps_p_eq;       ///< ≥ 0; empty without plasticity
  /// Per cell: the mean over its points (of σ, of the von Mises stress of each point, of ε̃^p
  /// and of the share of points that flowed in the step).
  std::vector<Voigt> cell_stress;
  std::vector<double> cell_von_mises, cell_eps_p_eq, cell_plastic_zone;
};

/// Collective over the ranks: root gets the fields of the whole model, the other ranks empty
/// vectors. On one rank, the fields of `state`. The cells' fields only `with_cells` (the
/// probes of every step need the nodal ones; the cells' are written on output steps only).
RecoveredFields recover_fields(const Model& model, const State& state, bool with_cells = true);

}  // namespace hencky
