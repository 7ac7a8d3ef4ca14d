#include "linalg/sparse.hpp"

#include <metis.h>
#include <omp.h>

#include <algorithm>
#include <numeric>

#include "core/invariant.hpp"

namespace hencky {

DofMap DofMap::from_constraints(int n_nodes, const std::vector<bool>& prescribed, int per_node) {
  DofMap m;
  m.per_node = per_node;
  m.eq.assign(static_cast<std::size_t>(per_node) * n_nodes, -1);
  for (std::size_t i = 0; i < m.eq.size(); ++i)
    if (!prescribed[i]) m.eq[i] = m.n_free++;
  return m;
}

std::int64_t SymmetricPattern::find(std::int64_t i, std::int64_t j) const {
  // Checked in every build: the binary search below costs far more than the comparison.
  HENCKY_VERIFY(i <= j, "SymmetricPattern::find: the upper triangle only (i <= j)");
  const auto b = row.begin() + col_ptr[j], e = row.begin() + col_ptr[j + 1];
  const auto it = std::lower_bound(b, e, i);
  return (it != e && *it == i) ? it - row.begin() : -1;
}

void node_cell_incidence(const CellSet& cells, int n_nodes, std::vector<int>& ptr,
                         std::vector<int>& idx) {
  ptr.assign(n_nodes + 1, 0);
  for (int n : cells.conn) ++ptr[n + 1];
  for (int i = 0; i < n_nodes; ++i) ptr[i + 1] += ptr[i];
  idx.resize(ptr.back());
  std::vector<int> fill(ptr.begin(), ptr.end() - 1);
  for (int c = 0; c < cells.size(); ++c)
    for (int n : cells.nodes(c)) idx[fill[n]++] = c;
}

std::vector<std::vector<int>> node_neighbours(const CellSet& cells, int n_nodes) {
  std::vector<int> nc_ptr, nc_idx;
  node_cell_incidence(cells, n_nodes, nc_ptr, nc_idx);
  std::vector<std::vector<int>> neighbours(n_nodes);
#pragma omp parallel
  {
    std::vector<int> mark(n_nodes, -1);
#pragma omp for schedule(dynamic, 256)
    for (int v = 0; v < n_nodes; ++v) {
      auto& nb = neighbours[v];
      for (int k = nc_ptr[v]; k < nc_ptr[v + 1]; ++k)
        for (int w : cells.nodes(nc_idx[k]))
          if (mark[w] != v) {
            mark[w] = v;
            nb.push_back(w);
          }
      std::sort(nb.begin(), nb.end());
    }
  }
  return neighbours;
}

SymmetricPattern build_pattern(const CellSet& cells, int n_nodes, const DofMap& dofs) {
  const std::vector<std::vector<int>> neighbours = node_neighbours(cells, n_nodes);

  // Column j (a free dof of node v) holds the free dofs i <= j of the neighbours of v.
  SymmetricPattern p;
  p.n = dofs.n_free;
  const int k = dofs.per_node;
  std::vector<int> dof_node(dofs.n_free);
  for (int v = 0; v < n_nodes; ++v)
    for (int d = 0; d < k; ++d)
      if (int j = dofs.eq[k * v + d]; j >= 0) dof_node[j] = v;
  for (std::int64_t j = 0; j < p.n; ++j)
    if (j == 0 || dof_node[j] != dof_node[j - 1]) p.group_start.push_back(j);
  p.group_start.push_back(p.n);
  std::vector<std::int64_t> count(p.n, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t j = 0; j < p.n; ++j) {
    std::int64_t c = 0;
    for (int w : neighbours[dof_node[j]])
      for (int d = 0; d < k; ++d)
        if (int i = dofs.eq[k * w + d]; i >= 0 && i <= j) ++c;
    count[j] = c;
  }
  p.col_ptr.assign(p.n + 1, 0);
  for (std::int64_t j = 0; j < p.n; ++j) p.col_ptr[j + 1] = p.col_ptr[j] + count[j];
  p.row.resize(p.col_ptr.back());
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t j = 0; j < p.n; ++j) {
    std::int64_t pos = p.col_ptr[j];
    for (int w : neighbours[dof_node[j]])
      for (int d = 0; d < k; ++d)
        if (int i = dofs.eq[k * w + d]; i >= 0 && i <= j) p.row[pos++] = i;
    std::sort(p.row.begin() + p.col_ptr[j], p.row.begin() + pos);
  }
  return p;
}

std::vector<std::int64_t> nested_dissection(const SymmetricPattern& p) {
  std::vector<std::int64_t> start = p.group_start;
  if (start.empty()) {
    start.resize(p.n + 1);
    std::iota(start.begin(), start.end(), std::int64_t{0});
  }
  const auto n_groups = static_cast<idx_t>(start.size() - 1);
  std::vector<idx_t> group(p.n);
  for (idx_t g = 0; g < n_groups; ++g)
    std::fill(group.begin() + start[g], group.begin() + start[g + 1], g);
  // The group graph from the upper triangle: an edge g–h (h < g) for every entry in a column
  // of g whose row is in h, stored in both directions, each once.
  std::vector<idx_t> mark(n_groups, -1), xadj(n_groups + 1, 0);
  auto for_each_lower = [&](idx_t g, auto&& f) {
    for (std::int64_t j = start[g]; j < start[g + 1]; ++j)
      for (std::int64_t k = p.col_ptr[j]; k < p.col_ptr[j + 1]; ++k)
        if (const idx_t h = group[p.row[k]]; h != g && mark[h] != g) {
          mark[h] = g;
          f(h);
        }
  };
  for (idx_t g = 0; g < n_groups; ++g)
    for_each_lower(g, [&](idx_t h) { ++xadj[g + 1], ++xadj[h + 1]; });
  for (idx_t g = 0; g < n_groups; ++g) xadj[g + 1] += xadj[g];
  std::vector<idx_t> adjncy(xadj.back()), fill(xadj.begin(), xadj.end() - 1);
  std::fill(mark.begin(), mark.end(), -1);
  for (idx_t g = 0; g < n_groups; ++g)
    for_each_lower(g, [&](idx_t h) { adjncy[fill[g]++] = h, adjncy[fill[h]++] = g; });
  // Weighted by their dofs, so that the separators balance the dofs (a node partly held has
  // fewer).
  std::vector<idx_t> weight(n_groups), perm(n_groups), iperm(n_groups);
  for (idx_t g = 0; g < n_groups; ++g) weight[g] = static_cast<idx_t>(start[g + 1] - start[g]);
  if (n_groups > 1) {
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    idx_t nv = n_groups;
    if (METIS_NodeND(&nv, xadj.data(), adjncy.data(), weight.data(), options, perm.data(),
                     iperm.data()) != METIS_OK)
      return {};
  } else {
    std::iota(perm.begin(), perm.end(), idx_t{0});
  }
  std::vector<std::int64_t> out;
  out.reserve(p.n);
  for (idx_t g : perm)
    for (std::int64_t j = start[g]; j < start[g + 1]; ++j) out.push_back(j);
  return out;
}

std::vector<std::vector<int>> color_cells(const CellSet& cells, int n_nodes) {
  // Greedy colouring with a 256-colour bit mask per node; meshes need far fewer colours
  // (a node touches a few dozen cells at most).
  constexpr int words = 4;
  std::vector<std::uint64_t> used(static_cast<std::size_t>(n_nodes) * words, 0);
  std::vector<std::vector<int>> colors;
  for (int c = 0; c < cells.size(); ++c) {
    std::uint64_t forbidden[words] = {0, 0, 0, 0};
    for (int n : cells.nodes(c))
      for (int w = 0; w < words; ++w) forbidden[w] |= used[n * words + w];
    int color = -1;
    for (int w = 0; w < words && color < 0; ++w)
      if (~forbidden[w]) color = 64 * w + __builtin_ctzll(~forbidden[w]);
    HENCKY_VERIFY(color >= 0, "more than 256 colours: a node shared by over 256 cells");
    if (color >= static_cast<int>(colors.size())) colors.resize(color + 1);
    colors[color].push_back(c);
    for (int n : cells.nodes(c)) used[n * words + color / 64] |= std::uint64_t{1} << (color % 64);
  }
  return colors;
}

}  // namespace hencky
