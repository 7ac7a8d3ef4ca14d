#include "solve/recovery.hpp"

#include <algorithm>
#include <array>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "material/elastic.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

RecoveredFields recover_fields(const Model& model, const State& state, bool with_cells) {
  const auto& mesh = model.mesh();
  const int n_nodes = mesh.n_nodes(), n_cells = mesh.cells.size();
  const bool plastic = model.has_plasticity();
  const bool updated = model.spec().solver.updated_geometry;
  // One buffer per target, so that the ranks' shares are summed in one reduction each: per
  // node the count of cells at it, σ, ε, ε^e, ε^th (6 each), then ε^p (6), ε̃^p and ε̃^{e+p}
  // with plasticity; per cell σ (6), σ_vM, ε̃^p, zone. Each rank counts the cells whose points it
  // holds, so that the counts sum like the values on any layout.
  constexpr int n_tensors = 4;  // σ, ε, ε^e, ε^th
  const int node_width = 1 + (plastic ? 6 * n_tensors + 8 : 6 * n_tensors), cell_width = 9;
  std::vector<double> nodal(static_cast<std::size_t>(node_width) * n_nodes, 0.0);
  std::vector<double> cells(with_cells ? static_cast<std::size_t>(cell_width) * n_cells : 0);
  CellKinematics kin;
  Vec3 x[max_cell_nodes];
  double u[3 * max_cell_nodes];
  std::array<Voigt, n_tensors> at_point[max_cell_points];  // σ, ε, ε^e, ε^th at each point
  for (int e = 0; e < n_cells; ++e) {
    const auto nodes = mesh.cells.nodes(e);
    if (!model.holds_points(e)) continue;
    const auto& tab = reference_table(mesh.cells.type[e]);
    const int p0 = model.point_offset(e), n_cell_nodes = static_cast<int>(nodes.size());
    if (!updated) {  // the total strain sym ∇u on the undeformed mesh
      for (int a = 0; a < n_cell_nodes; ++a) {
        x[a] = mesh.x[nodes[a]];
        for (int d = 0; d < 3; ++d) u[3 * a + d] = state.u[3 * nodes[a] + d];
      }
      kin.compute(tab, std::span<const Vec3>(x, n_cell_nodes));
    }
    for (int q = 0; q < tab.n_points; ++q) {
      const int p = p0 + q;
      const ElasticConstants& k = state.constants[p];
      const Voigt elastic = k.compliance() * state.stress[p];
      const Voigt thermal = volumetric(model.thermal_strain(e, k, state.temperature[p]));
      // Under `geometry: updated` the strain of the displacement on the undeformed mesh means
      // nothing once the body turns: the total strain is the sum of the objective increments,
      // elastic + plastic + thermal (the additive split the step's law keeps).
      const Voigt total =
          updated ? Voigt(elastic + state.plastic_strain[p] + thermal) : kin.strain(q, u);
      at_point[q] = {state.stress[p], total, elastic, thermal};
    }
    for (int a = 0; a < n_cell_nodes; ++a) {
      std::array<Voigt, n_tensors> t;
      t.fill(Voigt::Zero());
      Voigt eps_p = Voigt::Zero();
      double eqp = 0, eps_ep = 0;
      for (int q = 0; q < tab.n_points; ++q) {
        const double w = tab.extrapolation(a, q);
        for (int i = 0; i < n_tensors; ++i) t[i] += w * at_point[q][i];
        if (!plastic) continue;
        eps_p += w * state.plastic_strain[p0 + q];
        eqp += w * state.eps_p_eq[p0 + q];
        eps_ep += w * state.eps_ep[p0 + q];
      }
      double* v = &nodal[static_cast<std::size_t>(node_width) * nodes[a]];
      v[0] += 1;  // the count
      ++v;
      for (int i = 0; i < n_tensors; ++i)
        for (int k = 0; k < 6; ++k) v[6 * i + k] += t[i][k];
      if (!plastic) continue;
      for (int k = 0; k < 6; ++k) v[6 * n_tensors + k] += eps_p[k];
      v[6 * n_tensors + 6] += eqp;
      v[6 * n_tensors + 7] += eps_ep;
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
  // Every rank evaluates the probes in its own cells and, on an output step, writes the piece of
  // its own cells (results.hpp): each needs the nodal averages of its cells' nodes, ghost nodes
  // included. The sums go to every rank. A cell's means are its rank's alone.
  model.layout().sum(nodal, node_width);
  RecoveredFields f;
  std::vector<Voigt>* tensors[n_tensors] = {&f.nodal_stress, &f.nodal_strain,
                                            &f.nodal_elastic_strain, &f.nodal_thermal_strain};
  for (auto* t : tensors) t->assign(n_nodes, Voigt::Zero());
  if (plastic) {
    f.nodal_plastic_strain.assign(n_nodes, Voigt::Zero());
    f.nodal_eps_p_eq.assign(n_nodes, 0.0);
    f.nodal_eps_ep.assign(n_nodes, 0.0);
  }
  for (int n = 0; n < n_nodes; ++n) {
    const double* v = &nodal[static_cast<std::size_t>(node_width) * n];
    const double count = *v++;
    if (count == 0) continue;
    for (int i = 0; i < n_tensors; ++i)
      for (int k = 0; k < 6; ++k) (*tensors[i])[n][k] = v[6 * i + k] / count;
    if (!plastic) continue;
    for (int k = 0; k < 6; ++k) f.nodal_plastic_strain[n][k] = v[6 * n_tensors + k] / count;
    // Extrapolation from the points may undershoot next to a plastic zone's edge.
    f.nodal_eps_p_eq[n] = std::max(v[6 * n_tensors + 6] / count, 0.0);
    f.nodal_eps_ep[n] = v[6 * n_tensors + 7] / count;
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
