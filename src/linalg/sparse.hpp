#pragma once
// Global sparse structures, built once per analysis. The matrix is symmetric and only its
// upper triangle is stored, column by column (CSC, rows sorted), which is what CHOLMOD's
// stype = 1 expects and what Eigen maps as a ColMajor matrix viewed through `Upper`.
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/mesh.hpp"

namespace hencky {

/// Equation number of every nodal degree of freedom: eq[per_node*node + d], or -1 when
/// prescribed. per_node is 3 for the displacement, 1 for the temperature.
struct DofMap {
  std::vector<int> eq;
  int n_free = 0;
  int per_node = 3;
  int n_dofs() const { return static_cast<int>(eq.size()); }
  /// Numbers the free dofs node by node (the order keeps a node's dofs together);
  /// prescribed has per_node entries per node.
  static DofMap from_constraints(int n_nodes, const std::vector<bool>& prescribed,
                                 int per_node = 3);
};

struct SymmetricPattern {
  std::int64_t n = 0;
  std::vector<std::int64_t> col_ptr;  ///< n + 1 entries
  std::vector<std::int64_t> row;      ///< row indices (<= column), sorted within a column
  /// The dofs in groups of consecutive indices that share their couplings (a node's free
  /// dofs): group g is [group_start[g], group_start[g+1]). Empty: every dof its own group.
  std::vector<std::int64_t> group_start;
  std::int64_t nnz() const { return col_ptr.empty() ? 0 : col_ptr.back(); }
  /// Position of entry (i, j) with i <= j, or -1 when not in the pattern.
  std::int64_t find(std::int64_t i, std::int64_t j) const;
};

/// A fill-reducing ordering of the pattern's matrix: METIS nested dissection of the graph of
/// its groups (the nodes: a ninth of the dof graph's edges for 3 dofs per node), each group's
/// dofs then kept together in their order. perm[k] is the dof eliminated k-th.
std::vector<std::int64_t> nested_dissection(const SymmetricPattern& pattern);

/// Cells around each node (CSR): the cells of node n are idx[ptr[n] .. ptr[n+1]).
void node_cell_incidence(const CellSet& cells, int n_nodes, std::vector<int>& ptr,
                         std::vector<int>& idx);

/// The nodes coupled to each node through the cells, itself included, sorted. In parallel.
std::vector<std::vector<int>> node_neighbours(const CellSet& cells, int n_nodes);

/// Pattern of the free dofs coupled through the cells. Runs in parallel over nodes.
SymmetricPattern build_pattern(const CellSet& cells, int n_nodes, const DofMap& dofs);

/// Cells grouped so that no two cells of a group share a node: each group can be assembled in
/// parallel without locks or atomics.
std::vector<std::vector<int>> color_cells(const CellSet& cells, int n_nodes);

}  // namespace hencky
