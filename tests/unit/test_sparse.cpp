// The global sparse structures (linalg/sparse.hpp) and the direct solve on them: the node
// groups of the pattern, the node-graph nested dissection, and CHOLMOD with that ordering
// against a dense solve of the same matrix.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <numeric>
#include <random>

#include "core/error.hpp"
#include "linalg/sparse.hpp"
#include "linalg/sparse_solver.hpp"

namespace hencky {
namespace {

/// An n × n × n block of 8-node cells (CellType::hex8 is not needed by the pattern: only the
/// nodes are), (n+1)^3 nodes.
CellSet cube_cells(int n) {
  CellSet cells;
  auto id = [n](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int nodes[8] = {id(i, j, k),         id(i + 1, j, k),     id(i + 1, j + 1, k),
                              id(i, j + 1, k),     id(i, j, k + 1),     id(i + 1, j, k + 1),
                              id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        cells.add(CellType::hex8, nodes, 0);
      }
  return cells;
}

TEST(NestedDissection, KeepsEachNodesDofsTogetherInOrder) {
  const int n = 6, n_nodes = (n + 1) * (n + 1) * (n + 1);
  const CellSet cells = cube_cells(n);
  // The bottom face held, and one dof of a few other nodes: groups of 3, 2 and 0 dofs.
  std::vector<bool> prescribed(3 * n_nodes, false);
  for (int v = 0; v < (n + 1) * (n + 1); ++v)
    for (int d = 0; d < 3; ++d) prescribed[3 * v + d] = true;
  for (int v = n_nodes - 10; v < n_nodes; v += 3) prescribed[3 * v + 1] = true;
  const DofMap dofs = DofMap::from_constraints(n_nodes, prescribed);
  const SymmetricPattern p = build_pattern(cells, n_nodes, dofs);

  ASSERT_EQ(p.group_start.front(), 0);
  ASSERT_EQ(p.group_start.back(), p.n);
  EXPECT_EQ(static_cast<int>(p.group_start.size()) - 1, n_nodes - (n + 1) * (n + 1));

  const std::vector<std::int64_t> perm = nested_dissection(p);
  ASSERT_EQ(static_cast<std::int64_t>(perm.size()), p.n);
  std::vector<std::int64_t> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  for (std::int64_t i = 0; i < p.n; ++i) ASSERT_EQ(sorted[i], i) << "not a permutation";
  // Every group appears as a run of its dofs in increasing order.
  for (std::size_t g = 0; g + 1 < p.group_start.size(); ++g) {
    const auto first = std::find(perm.begin(), perm.end(), p.group_start[g]);
    for (std::int64_t j = p.group_start[g]; j < p.group_start[g + 1]; ++j)
      EXPECT_EQ(*(first + (j - p.group_start[g])), j) << "group " << g;
  }
}

TEST(NestedDissection, CholmodWithItSolvesAsADenseFactorization) {
  const int n = 5, n_nodes = (n + 1) * (n + 1) * (n + 1);
  const CellSet cells = cube_cells(n);
  std::vector<bool> prescribed(3 * n_nodes, false);
  for (int d = 0; d < 3; ++d) prescribed[d] = true;
  const DofMap dofs = DofMap::from_constraints(n_nodes, prescribed);
  const SymmetricPattern p = build_pattern(cells, n_nodes, dofs);
  // A random symmetric matrix on the pattern, made positive definite by its diagonal.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> values(p.nnz());
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(p.n, p.n);
  for (std::int64_t j = 0; j < p.n; ++j)
    for (std::int64_t k = p.col_ptr[j]; k < p.col_ptr[j + 1]; ++k) {
      const std::int64_t i = p.row[k];
      values[k] = i == j ? 100.0 : u(rng);
      dense(i, j) = dense(j, i) = values[k];
    }
  Eigen::VectorXd b(p.n);
  for (std::int64_t i = 0; i < p.n; ++i) b[i] = u(rng);

  auto solver = make_sparse_solver(LinearSolverKind::direct);
  solver->analyze(p);
  solver->factorize(values);
  Eigen::VectorXd x(p.n);
  solver->solve({b.data(), static_cast<std::size_t>(p.n)}, {x.data(), static_cast<std::size_t>(p.n)});
  const Eigen::VectorXd expected = dense.llt().solve(b);
  EXPECT_LT((x - expected).norm(), 1e-12 * expected.norm());
  EXPECT_NE(solver->stats().description.find("node-graph METIS"), std::string::npos)
      << solver->stats().description;
}

// A failed pivot is reported at its unknown in the system's own numbering, whatever the
// fill-reducing order put it at (issue 47: "an indefinite matrix later in a run says where").
TEST(NestedDissection, AFailedPivotNamesItsUnknownInTheSystemsNumbering) {
  const int n = 4, n_nodes = (n + 1) * (n + 1) * (n + 1);
  const CellSet cells = cube_cells(n);
  const DofMap dofs = DofMap::from_constraints(n_nodes, std::vector<bool>(3 * n_nodes, false));
  const SymmetricPattern p = build_pattern(cells, n_nodes, dofs);
  for (const std::int64_t bad : {std::int64_t{0}, p.n / 2 + 1, p.n - 1}) {
    // Diagonally dominant but for one negative diagonal entry: every pivot before it in any
    // order stays positive, and its own is negative.
    std::vector<double> values(p.nnz());
    for (std::int64_t j = 0; j < p.n; ++j)
      for (std::int64_t k = p.col_ptr[j]; k < p.col_ptr[j + 1]; ++k)
        values[k] = p.row[k] == j ? (j == bad ? -100.0 : 100.0) : 0.5;
    auto solver = make_sparse_solver(LinearSolverKind::direct);
    solver->analyze(p);
    try {
      solver->factorize(values);
      ADD_FAILURE() << "an indefinite matrix was factorized (unknown " << bad << ")";
    } catch (const LinearSystemError& e) {
      EXPECT_EQ(e.kind(), LinearSystemError::Kind::not_positive_definite);
      EXPECT_EQ(e.equation(), bad) << e.what();
    }
  }
}

TEST(NestedDissection, TheNodeGraphPredictsTheDofFactor) {
  // estimate_factor (the node graph's factor scaled to 3 dofs a node) against the analysis of
  // the dofs themselves, nothing prescribed.
  const int n = 10, n_nodes = (n + 1) * (n + 1) * (n + 1);
  const CellSet cells = cube_cells(n);
  const DofMap dofs = DofMap::from_constraints(n_nodes, std::vector<bool>(3 * n_nodes, false));
  const SymmetricPattern p = build_pattern(cells, n_nodes, dofs);
  auto solver = make_sparse_solver(LinearSolverKind::direct);
  solver->analyze(p);
  const FactorEstimate e = estimate_factor(cells, n_nodes);
  EXPECT_NEAR(e.entries_for(3) / solver->stats().factor_nnz, 1.0, 0.05);
  EXPECT_NEAR(e.flops_for(3) / solver->stats().factor_flops, 1.0, 0.10);
}

}  // namespace
}  // namespace hencky
