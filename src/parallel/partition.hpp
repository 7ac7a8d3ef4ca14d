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

/// The split of `mesh` into `parts` pieces for rank `rank`: METIS k-way on the dual graph of the
/// corner nodes (three shared corners make a neighbour). One part owns everything. Collective
/// when parts > 1 (rank 0 partitions, the others receive).
Partition partition_mesh(const Mesh& mesh, int parts, int rank);

}  // namespace hencky
