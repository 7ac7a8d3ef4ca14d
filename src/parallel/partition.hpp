#pragma once
// Which rank owns which element and node. The mesh is read whole by every rank (replicated);
// the elements are split by METIS over the dual graph (elements sharing a face), computed on
// rank 0 and broadcast, so that every rank holds the same split. A node belongs to the lowest
// rank among the owners of its elements; its three rows of the global matrix live there.
#include <vector>

#include "mesh/mesh.hpp"

namespace hencky {

struct Partition {
  int parts = 1;
  int rank = 0;
  std::vector<int> cell_owner;  ///< rank of each cell
  std::vector<int> node_owner;  ///< rank of each node
  std::vector<char> owned_cell; ///< 1 for the cells of this rank
  int owned_cells = 0;
  int owned_nodes = 0;
  bool owns_cell(int c) const { return owned_cell[c] != 0; }
};

/// The owner of each cell: METIS k-way on the dual graph of the corner nodes (three shared
/// corners make a neighbour). One part owns everything; fewer than 2 cells a part are dealt
/// round-robin. Deterministic (fixed seed).
std::vector<int> split_cells(const Mesh& mesh, int parts);

/// Rank `rank`'s view of the split `cell_owner` (node owners, own cells, counts).
Partition partition_from(const Mesh& mesh, std::vector<int> cell_owner, int parts, int rank);

/// split_cells on rank 0, broadcast to all, and each rank's view. Collective when parts > 1.
Partition partition_mesh(const Mesh& mesh, int parts, int rank);

}  // namespace hencky
