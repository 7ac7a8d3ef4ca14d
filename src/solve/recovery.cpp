#include "solve/recovery.hpp"

#include <algorithm>
#include <array>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "material/elastic.hpp"
#include "parallel/mpi.hpp"
#include "solve/element_matrix.hpp"

namespace hencky {
namespace {

// The ranks' shares are packed into one buffer per target, so that each is summed in one
// reduction: a record of numbers per node and one per cell. Each rank counts the cells whose
// points it holds, so that the counts sum like the values on any layout. The records' fields
// are named here, once.

constexpr int n_tensors = 4;  // σ, ε, ε^e, ε^th
using PointTensors = std::array<Voigt, n_tensors>;

/// A node's record: the count of cells at it, σ, ε, ε^e, ε^th (6 each, summed over its cells'
/// extrapolations), then with plasticity ε^p (6), ε̃^p, ε̃^{e+p} and the law's internal
/// variables (`law` numbers, Model::law_state_size()).
struct NodeRecord {
  static constexpr int count = 0;
  static constexpr int tensors = count + 1;  ///< tensor i at tensors + 6 i
  static constexpr int plastic_strain = tensors + 6 * n_tensors;
  static constexpr int eps_p_eq = plastic_strain + 6;
  static constexpr int eps_ep = eps_p_eq + 1;
  static constexpr int internal = eps_ep + 1;
  /// Numbers a node: the plastic fields only with plasticity.
  static constexpr int width(bool plastic, int law) {
    return plastic ? internal + law : plastic_strain;
  }
};

/// A cell's record: the sums over its points of σ (6), σ_vM, ε̃^p and the flowing flag (its
/// means once divided by the point count).
struct CellRecord {
  static constexpr int stress = 0;
  static constexpr int von_mises = stress + 6;
  static constexpr int eps_p_eq = von_mises + 1;
  static constexpr int flowing = eps_p_eq + 1;
  static constexpr int width = flowing + 1;
};

/// σ, ε, ε^e and ε^th at each point of cell `e`; `kin` is scratch.
void point_tensors(const Model& model, const State& state, int e, CellKinematics& kin,
                   PointTensors* at_point) {
  const auto& mesh = model.mesh();
  const auto nodes = mesh.cells.nodes(e);
  const auto& tab = reference_table(mesh.cells.type[e]);
  const int p0 = model.point_offset(e), n_cell_nodes = static_cast<int>(nodes.size());
  const bool updated = model.spec().solver.updated_geometry;
  Vec3 x[max_cell_nodes];
  double u[3 * max_cell_nodes];
  // The total strain sym ∇u on the undeformed mesh; under `updated`, ∇u gives J = det F.
  for (int a = 0; a < n_cell_nodes; ++a) {
    x[a] = mesh.x[nodes[a]];
    for (int d = 0; d < 3; ++d) u[3 * a + d] = state.u[3 * nodes[a] + d];
  }
  kin.compute(tab, std::span<const Vec3>(x, n_cell_nodes));
  for (int q = 0; q < tab.n_points; ++q) {
    const int p = p0 + q;
    const ElasticConstants& k = state.constants[p];
    // Under `updated` the elastic strain is Hencky's, A τ with the Kirchhoff stress τ = Jσ.
    const double j =
        updated ? (Mat3::Identity() + kin.gradient(q, u)).determinant() : 1.0;
    const Voigt elastic = k.compliance() * (updated ? Voigt(j * state.stress[p]) : state.stress[p]);
    const Voigt thermal = volumetric(model.thermal_strain(e, k, state.temperature[p]));
    // Under `geometry: updated` the strain of the displacement on the undeformed mesh means
    // nothing once the body turns: the total strain is the sum of the objective increments,
    // elastic + plastic + thermal (the additive split the step's law keeps).
    const Voigt total =
        updated ? Voigt(elastic + state.plastic_strain[p] + thermal) : kin.strain(q, u);
    at_point[q] = {state.stress[p], total, elastic, thermal};
  }
}

/// Adds cell `e`'s extrapolation of its point values to the records of its nodes.
void add_to_nodes(const Model& model, const State& state, int e, const PointTensors* at_point,
                  std::vector<double>& nodal) {
  const auto& mesh = model.mesh();
  const auto nodes = mesh.cells.nodes(e);
  const auto& tab = reference_table(mesh.cells.type[e]);
  const int p0 = model.point_offset(e);
  const bool plastic = model.has_plasticity();
  const int n_law = model.law_state_size();
  const int width = NodeRecord::width(plastic, n_law);
  for (std::size_t a = 0; a < nodes.size(); ++a) {
    PointTensors t;
    t.fill(Voigt::Zero());
    Voigt eps_p = Voigt::Zero();
    double eqp = 0, eps_ep = 0;
    for (int q = 0; q < tab.n_points; ++q) {
      const double w = tab.extrapolation(static_cast<int>(a), q);
      for (int i = 0; i < n_tensors; ++i) t[i] += w * at_point[q][i];
      if (!plastic) continue;
      eps_p += w * state.plastic_strain[p0 + q];
      eqp += w * state.eps_p_eq[p0 + q];
      eps_ep += w * state.eps_ep[p0 + q];
    }
    double* v = &nodal[static_cast<std::size_t>(width) * nodes[a]];
    v[NodeRecord::count] += 1;
    for (int i = 0; i < n_tensors; ++i)
      for (int k = 0; k < 6; ++k) v[NodeRecord::tensors + 6 * i + k] += t[i][k];
    if (!plastic) continue;
    for (int k = 0; k < 6; ++k) v[NodeRecord::plastic_strain + k] += eps_p[k];
    v[NodeRecord::eps_p_eq] += eqp;
    v[NodeRecord::eps_ep] += eps_ep;
    for (int q = 0; q < tab.n_points && n_law > 0; ++q) {
      const double w = tab.extrapolation(static_cast<int>(a), q);
      const double* s = state.internal.data() + static_cast<std::size_t>(p0 + q) * n_law;
      for (int j = 0; j < n_law; ++j) v[NodeRecord::internal + j] += w * s[j];
    }
  }
}

/// Adds cell `e`'s points to its record (the means as sums; divided in cell_means).
void add_cell_sums(const Model& model, const State& state, int e, std::vector<double>& cells) {
  const int p0 = model.point_offset(e);
  const int n_points = reference_table(model.mesh().cells.type[e]).n_points;
  double* c = &cells[static_cast<std::size_t>(CellRecord::width) * e];
  for (int p = p0; p < p0 + n_points; ++p) {
    for (int k = 0; k < 6; ++k) c[CellRecord::stress + k] += state.stress[p][k];
    c[CellRecord::von_mises] += von_mises(state.stress[p]);
    c[CellRecord::eps_p_eq] += state.eps_p_eq[p];
    c[CellRecord::flowing] += static_cast<double>(state.flowing[p]);
  }
}

/// The nodal fields of `f`: each node's summed record over its count of cells.
void nodal_means(const std::vector<double>& nodal, int n_nodes, bool plastic, int n_law,
                 RecoveredFields& f) {
  const int width = NodeRecord::width(plastic, n_law);
  std::vector<Voigt>* tensors[n_tensors] = {&f.nodal_stress, &f.nodal_strain,
                                            &f.nodal_elastic_strain, &f.nodal_thermal_strain};
  for (auto* t : tensors) t->assign(n_nodes, Voigt::Zero());
  if (plastic) {
    f.nodal_plastic_strain.assign(n_nodes, Voigt::Zero());
    f.nodal_eps_p_eq.assign(n_nodes, 0.0);
    f.nodal_eps_ep.assign(n_nodes, 0.0);
    f.nodal_internal.assign(static_cast<std::size_t>(n_nodes) * n_law, 0.0);
  }
  for (int n = 0; n < n_nodes; ++n) {
    const double* v = &nodal[static_cast<std::size_t>(width) * n];
    const double count = v[NodeRecord::count];
    if (count == 0) continue;
    for (int i = 0; i < n_tensors; ++i)
      for (int k = 0; k < 6; ++k) (*tensors[i])[n][k] = v[NodeRecord::tensors + 6 * i + k] / count;
    if (!plastic) continue;
    for (int k = 0; k < 6; ++k)
      f.nodal_plastic_strain[n][k] = v[NodeRecord::plastic_strain + k] / count;
    // Extrapolation from the points may undershoot next to a plastic zone's edge.
    f.nodal_eps_p_eq[n] = std::max(v[NodeRecord::eps_p_eq] / count, 0.0);
    f.nodal_eps_ep[n] = v[NodeRecord::eps_ep] / count;
    for (int j = 0; j < n_law; ++j)
      f.nodal_internal[static_cast<std::size_t>(n) * n_law + j] =
          v[NodeRecord::internal + j] / count;
  }
}

/// The cell fields of `f`: each cell's record over its count of points.
void cell_means(const Mesh& mesh, const std::vector<double>& cells, RecoveredFields& f) {
  const int n_cells = mesh.cells.size();
  f.cell_stress.resize(n_cells);
  f.cell_von_mises.resize(n_cells);
  f.cell_eps_p_eq.resize(n_cells);
  f.cell_plastic_zone.resize(n_cells);
  for (int e = 0; e < n_cells; ++e) {
    const double* c = &cells[static_cast<std::size_t>(CellRecord::width) * e];
    const int n_points = reference_table(mesh.cells.type[e]).n_points;
    for (int k = 0; k < 6; ++k) f.cell_stress[e][k] = c[CellRecord::stress + k];
    f.cell_stress[e] /= n_points;
    f.cell_von_mises[e] = c[CellRecord::von_mises] / n_points;
    f.cell_eps_p_eq[e] = c[CellRecord::eps_p_eq] / n_points;
    f.cell_plastic_zone[e] = c[CellRecord::flowing] / n_points;
  }
}

}  // namespace

void point_strains(const Model& model, const State& state, int e, std::vector<Voigt>& strain) {
  // Called cell by cell (MODEL.dat's E): the thread's scratch, not 26 kB zeroed per cell.
  PointTensors at_point[max_cell_points];
  point_tensors(model, state, e, thread_kinematics(), at_point);
  const int n = reference_table(model.mesh().cells.type[e]).n_points;
  strain.resize(static_cast<std::size_t>(n));
  for (int q = 0; q < n; ++q) strain[static_cast<std::size_t>(q)] = at_point[q][1];
}

RecoveredFields recover_fields(const Model& model, const State& state, bool with_cells) {
  const auto& mesh = model.mesh();
  const int n_nodes = mesh.n_nodes(), n_cells = mesh.cells.size();
  const bool plastic = model.has_plasticity();
  const int n_law = model.law_state_size();
  const int node_width = NodeRecord::width(plastic, n_law);
  std::vector<double> nodal(static_cast<std::size_t>(node_width) * n_nodes, 0.0);
  std::vector<double> cells(with_cells ? static_cast<std::size_t>(CellRecord::width) * n_cells : 0);
  CellKinematics kin;
  PointTensors at_point[max_cell_points];
  for (int e = 0; e < n_cells; ++e) {
    if (!model.holds_points(e)) continue;
    point_tensors(model, state, e, kin, at_point);
    add_to_nodes(model, state, e, at_point, nodal);
    if (with_cells) add_cell_sums(model, state, e, cells);
  }
  // Every rank evaluates the probes in its own cells and, on an output step, writes the piece of
  // its own cells (results.hpp): each needs the nodal averages of its cells' nodes, ghost nodes
  // included. The sums go to every rank. A cell's means are its rank's alone.
  model.layout().sum(nodal, node_width);
  RecoveredFields f;
  nodal_means(nodal, n_nodes, plastic, n_law, f);
  if (with_cells) cell_means(mesh, cells, f);
  return f;
}

}  // namespace hencky
