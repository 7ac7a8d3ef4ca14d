#pragma once
// The integration-point values of a converged step brought to the nodes and the cells, for
// the outputs (fields, probes). On several MPI ranks each rank holds only its own cells'
// points (Model::set_partition): each computes its cells' share, and the nodes' sums are reduced.
#include <vector>

#include "solve/analysis.hpp"

namespace hencky {

struct RecoveredFields {
  /// Per node: each cell extrapolates its point values to its nodes
  /// (reference_table().extrapolation), a node averages over all its cells.
  std::vector<Voigt> nodal_stress;
  std::vector<Voigt> nodal_plastic_strain;  ///< engineering shears; empty without plasticity
  std::vector<double> nodal_eps_p_eq;       ///< ≥ 0; empty without plasticity
  /// The strains, engineering shears (issue 17): the total ε = sym ∇u, the thermal
  /// ε^th = (α(T)·T − α(T_ref)·T_ref)·δ and the elastic ε^e = A(T)σ, the strain the stress
  /// carries (A the compliance). The update (1.12)-(1.14) keeps ε = ε^e + ε^p + ε^th at
  /// every point (to round-off where elastic, to the tolerance where the schemes iterate).
  std::vector<Voigt> nodal_strain, nodal_elastic_strain, nodal_thermal_strain;
  /// ε̃^{e+p}, the scalar the schemes advance along the curve; empty without plasticity.
  std::vector<double> nodal_eps_ep;
  /// The point law's internal variables (Model::law_variables), Model::law_state_size()
  /// numbers per node; empty where no law has any.
  std::vector<double> nodal_internal;
  /// Per cell: the mean over its points (of σ, of the von Mises stress of each point, of ε̃^p
  /// and of the share of points that flowed in the step).
  std::vector<Voigt> cell_stress;
  std::vector<double> cell_von_mises, cell_eps_p_eq, cell_plastic_zone;
};

/// Collective over the ranks. On one rank, the fields of `state`. The cells' fields only
/// `with_cells` (the probes of every step need the nodal ones; the cells' are written on output
/// steps only). On several ranks every rank gets the nodal fields of the whole model (for the
/// probes in its cells and its piece of the output) and the cells' fields of its own cells
/// (zero elsewhere).
RecoveredFields recover_fields(const Model& model, const State& state, bool with_cells = true);

/// The total strain ε at each integration point of cell `e` (this rank's), engineering shears,
/// as the fields' `strain` takes it: sym ∇u on the undeformed mesh, under `geometry: updated`
/// the sum ε^e + ε^p + ε^th of the objective increments. `strain` is resized to the points.
void point_strains(const Model& model, const State& state, int e, std::vector<Voigt>& strain);

}  // namespace hencky
