#include "solve/recovery.hpp"

#include <algorithm>

#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

RecoveredFields recover_fields(const Model& model, const State& state, bool with_cells) {
  const auto& mesh = model.mesh();
  const int n_nodes = mesh.n_nodes(), n_cells = mesh.cells.size();
  const bool plastic = model.has_plasticity();
  // One buffer per target, so that the ranks' shares are summed in one reduction each: per
  // node σ (6), then ε^p (6) and ε̃^p (1) with plasticity; per cell σ (6), σ_vM, ε̃^p, zone.
  const int node_width = plastic ? 13 : 6, cell_width = 9;
  std::vector<double> nodal(static_cast<std::size_t>(node_width) * n_nodes, 0.0);
  std::vector<double> cells(with_cells ? static_cast<std::size_t>(cell_width) * n_cells : 0);
  std::vector<int> count(n_nodes, 0);  // cells at each node, over all ranks (the mesh is whole)
  for (int e = 0; e < n_cells; ++e) {
    const auto nodes = mesh.cells.nodes(e);
    for (int n : nodes) ++count[n];
    if (!model.holds_points(e)) continue;
    const auto& tab = reference_table(mesh.cells.type[e]);
    const int p0 = model.point_offset(e);
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      Voigt sigma = Voigt::Zero(), eps_p = Voigt::Zero();
      double eqp = 0;
      for (int q = 0; q < tab.n_points; ++q) {
        const double w = tab.extrapolation(static_cast<int>(a), q);
        sigma += w * state.stress[p0 + q];
        if (!plastic) continue;
        eps_p += w * state.plastic_strain[p0 + q];
        eqp += w * state.eps_p_eq[p0 + q];
      }
      double* v = &nodal[static_cast<std::size_t>(node_width) * nodes[a]];
      for (int k = 0; k < 6; ++k) v[k] += sigma[k];
      if (!plastic) continue;
      for (int k = 0; k < 6; ++k) v[6 + k] += eps_p[k];
      v[12] += eqp;
    }
    if (!with_cells) continue;
    // The cell means, as sums here (divided on root).
    double* c = &cells[static_cast<std::size_t>(cell_width) * e];
    for (int p = p0; p < p0 + tab.n_points; ++p) {
      for (int k = 0; k < 6; ++k) c[k] += state.stress[p][k];
      c[6] += von_mises(state.stress[p]);
      c[7] += state.eps_p_eq[p];
      c[8] += static_cast<double>(state.flowing[p]);
    }
  }
  par::sum_to_root(std::span<double>(nodal));
  if (with_cells) par::sum_to_root(std::span<double>(cells));
  RecoveredFields f;
  if (!par::root()) return f;
  f.nodal_stress.assign(n_nodes, Voigt::Zero());
  if (plastic) {
    f.nodal_plastic_strain.assign(n_nodes, Voigt::Zero());
    f.nodal_eps_p_eq.assign(n_nodes, 0.0);
  }
  for (int n = 0; n < n_nodes; ++n) {
    if (count[n] == 0) continue;
    const double* v = &nodal[static_cast<std::size_t>(node_width) * n];
    for (int k = 0; k < 6; ++k) f.nodal_stress[n][k] = v[k] / count[n];
    if (!plastic) continue;
    for (int k = 0; k < 6; ++k) f.nodal_plastic_strain[n][k] = v[6 + k] / count[n];
    // Extrapolation from the points may undershoot next to a plastic zone's edge.
    f.nodal_eps_p_eq[n] = std::max(v[12] / count[n], 0.0);
  }
  if (!with_cells) return f;
  f.cell_stress.resize(n_cells);
  f.cell_von_mises.resize(n_cells);
  f.cell_eps_p_eq.resize(n_cells);
  f.cell_plastic_zone.resize(n_cells);
  for (int e = 0; e < n_cells; ++e) {
    const double* c = &cells[static_cast<std::size_t>(cell_width) * e];
    const int n_points = reference_table(mesh.cells.type[e]).n_points;
    for (int k = 0; k < 6; ++k) f.cell_stress[e][k] = c[k];
    f.cell_stress[e] /= n_points;
    f.cell_von_mises[e] = c[6] / n_points;
    f.cell_eps_p_eq[e] = c[7] / n_points;
    f.cell_plastic_zone[e] = c[8] / n_points;
  }
  return f;
}

}  // namespace hencky
