#include "parallel/partition.hpp"

#include <metis.h>

#include <algorithm>
#include <stdexcept>

#include "parallel/mpi.hpp"

namespace hencky {

namespace {

/// METIS k-way over the dual graph (corner nodes; three shared corners make two cells
/// neighbours: a face of a tetrahedron, or more than an edge of a hexahedron).
std::vector<int> metis_cells(const Mesh& mesh, int parts) {
  const int n_cells = mesh.cells.size();
  std::vector<idx_t> eptr(n_cells + 1, 0), eind;
  for (int c = 0; c < n_cells; ++c) {
    const auto nodes = mesh.cells.nodes(c);
    const int nc = cell_n_corners(mesh.cells.type[c]);
    eind.insert(eind.end(), nodes.begin(), nodes.begin() + nc);
    eptr[c + 1] = static_cast<idx_t>(eind.size());
  }
  idx_t ne = n_cells, nn = mesh.n_nodes(), ncommon = 3, nparts = parts, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;  // the same split every run
  std::vector<idx_t> epart(n_cells), npart(mesh.n_nodes());
  const int status = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr,
                                        &ncommon, &nparts, nullptr, options, &objval,
                                        epart.data(), npart.data());
  if (status != METIS_OK)
    throw std::runtime_error("METIS could not partition the mesh (status " +
                             std::to_string(status) + ")");
  return {epart.begin(), epart.end()};
}

}  // namespace

std::vector<int> split_cells(const Mesh& mesh, int parts) {
  const int n_cells = mesh.cells.size();
  if (parts > 1 && n_cells >= 2 * parts) return metis_cells(mesh, parts);
  std::vector<int> owner(n_cells, 0);
  for (int c = 0; c < n_cells; ++c) owner[c] = c % parts;
  return owner;
}

Partition partition_from(const Mesh& mesh, std::vector<int> cell_owner, int parts, int rank) {
  Partition p;
  p.parts = parts;
  p.rank = rank;
  p.cell_owner = std::move(cell_owner);
  const int n_cells = mesh.cells.size();
  p.node_owner.assign(mesh.n_nodes(), parts);
  for (int c = 0; c < n_cells; ++c)
    for (int n : mesh.cells.nodes(c)) p.node_owner[n] = std::min(p.node_owner[n], p.cell_owner[c]);
  // A node of no cell (a stray mesh node) belongs to rank 0; it carries no stiffness and is
  // held by the constraints of the model.
  for (int& o : p.node_owner)
    if (o == parts) o = 0;
  p.owned_cell.assign(n_cells, 0);
  for (int c = 0; c < n_cells; ++c) {
    p.owned_cell[c] = p.cell_owner[c] == rank;
    p.owned_cells += p.owned_cell[c];
  }
  p.owned_nodes = static_cast<int>(std::count(p.node_owner.begin(), p.node_owner.end(), rank));
  return p;
}

Partition partition_mesh(const Mesh& mesh, int parts, int rank) {
  std::vector<int> owner(mesh.cells.size(), 0);
  if (parts > 1) {
    if (rank == 0) owner = split_cells(mesh, parts);
    par::broadcast(std::span<int>(owner));
  }
  return partition_from(mesh, std::move(owner), parts, rank);
}

}  // namespace hencky
