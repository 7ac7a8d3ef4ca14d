#include "fem/reference_element.hpp"

#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "core/invariant.hpp"
#include "fem/quadrature.hpp"

namespace hencky {
namespace {

// Node coordinates, stride 3, Gmsh ordering.
// clang-format off
constexpr double tet4_nodes[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
constexpr double tet10_nodes[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,  // corners
                                  0.5, 0, 0,    // 4: (0,1)
                                  0.5, 0.5, 0,  // 5: (1,2)
                                  0, 0.5, 0,    // 6: (2,0)
                                  0, 0, 0.5,    // 7: (3,0)
                                  0, 0.5, 0.5,  // 8: (3,2)
                                  0.5, 0, 0.5}; // 9: (3,1)
constexpr double hex20_nodes[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,  // corners zeta = -1
                                  -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1,   // corners zeta = +1
                                  0, -1, -1,   // 8: (0,1)
                                  -1, 0, -1,   // 9: (0,3)
                                  -1, -1, 0,   // 10: (0,4)
                                  1, 0, -1,    // 11: (1,2)
                                  1, -1, 0,    // 12: (1,5)
                                  0, 1, -1,    // 13: (2,3)
                                  1, 1, 0,     // 14: (2,6)
                                  -1, 1, 0,    // 15: (3,7)
                                  0, -1, 1,    // 16: (4,5)
                                  -1, 0, 1,    // 17: (4,7)
                                  1, 0, 1,     // 18: (5,6)
                                  0, 1, 1};    // 19: (6,7)
constexpr double wedge6_nodes[] = {0, 0, -1, 1, 0, -1, 0, 1, -1, 0, 0, 1, 1, 0, 1, 0, 1, 1};
constexpr double tri6_nodes[] = {0, 0, 0, 1, 0, 0, 0, 1, 0,  // corners
                                 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0};
constexpr double quad8_nodes[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0,  // corners
                                  0, -1, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0};
// clang-format on
// The linear cells' nodes are the first nodes of the quadratic ones.
constexpr const double* hex_nodes = hex20_nodes;
constexpr const double* quad_nodes = quad8_nodes;

constexpr int tet10_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
constexpr int tri6_edges[3][2] = {{0, 1}, {1, 2}, {2, 0}};

}  // namespace

const double* node_coordinates(CellType type) {
  switch (type) {
    case CellType::tet4:
      return tet4_nodes;
    case CellType::tet10:
      return tet10_nodes;
    case CellType::hex8:
    case CellType::hex20:
      return hex20_nodes;
    case CellType::wedge6:
      return wedge6_nodes;
    case CellType::tri3:
    case CellType::tri6:
      return tri6_nodes;
    case CellType::quad4:
    case CellType::quad8:
      return quad8_nodes;
  }
  return nullptr;
}

void shape_values(CellType type, const double* x, double* N) {
  switch (type) {
    case CellType::tet4:
      N[0] = 1.0 - x[0] - x[1] - x[2];
      N[1] = x[0];
      N[2] = x[1];
      N[3] = x[2];
      return;
    case CellType::tet10: {
      const double L[4] = {1.0 - x[0] - x[1] - x[2], x[0], x[1], x[2]};
      for (int a = 0; a < 4; ++a) N[a] = L[a] * (2.0 * L[a] - 1.0);
      for (int e = 0; e < 6; ++e) N[4 + e] = 4.0 * L[tet10_edges[e][0]] * L[tet10_edges[e][1]];
      return;
    }
    case CellType::hex8:
      for (int a = 0; a < 8; ++a) {
        const double* c = hex_nodes + 3 * a;
        N[a] = 0.125 * (1.0 + c[0] * x[0]) * (1.0 + c[1] * x[1]) * (1.0 + c[2] * x[2]);
      }
      return;
    case CellType::hex20:
      for (int a = 0; a < 20; ++a) {
        const double* c = hex20_nodes + 3 * a;
        const double p = 1.0 + c[0] * x[0], q = 1.0 + c[1] * x[1], r = 1.0 + c[2] * x[2];
        if (a < 8)
          N[a] = 0.125 * p * q * r * (c[0] * x[0] + c[1] * x[1] + c[2] * x[2] - 2.0);
        else if (c[0] == 0.0)
          N[a] = 0.25 * (1.0 - x[0] * x[0]) * q * r;
        else if (c[1] == 0.0)
          N[a] = 0.25 * p * (1.0 - x[1] * x[1]) * r;
        else
          N[a] = 0.25 * p * q * (1.0 - x[2] * x[2]);
      }
      return;
    case CellType::wedge6: {
      const double L[3] = {1.0 - x[0] - x[1], x[0], x[1]};
      const double lo = 0.5 * (1.0 - x[2]), hi = 0.5 * (1.0 + x[2]);
      for (int a = 0; a < 3; ++a) {
        N[a] = L[a] * lo;
        N[a + 3] = L[a] * hi;
      }
      return;
    }
    case CellType::tri3:
      N[0] = 1.0 - x[0] - x[1];
      N[1] = x[0];
      N[2] = x[1];
      return;
    case CellType::tri6: {
      const double L[3] = {1.0 - x[0] - x[1], x[0], x[1]};
      for (int a = 0; a < 3; ++a) N[a] = L[a] * (2.0 * L[a] - 1.0);
      for (int e = 0; e < 3; ++e) N[3 + e] = 4.0 * L[tri6_edges[e][0]] * L[tri6_edges[e][1]];
      return;
    }
    case CellType::quad4:
      for (int a = 0; a < 4; ++a) {
        const double* c = quad_nodes + 3 * a;
        N[a] = 0.25 * (1.0 + c[0] * x[0]) * (1.0 + c[1] * x[1]);
      }
      return;
    case CellType::quad8:
      for (int a = 0; a < 8; ++a) {
        const double* c = quad8_nodes + 3 * a;
        const double p = 1.0 + c[0] * x[0], q = 1.0 + c[1] * x[1];
        if (a < 4)
          N[a] = 0.25 * p * q * (c[0] * x[0] + c[1] * x[1] - 1.0);
        else if (c[0] == 0.0)
          N[a] = 0.5 * (1.0 - x[0] * x[0]) * q;
        else
          N[a] = 0.5 * p * (1.0 - x[1] * x[1]);
      }
      return;
  }
}

namespace {

// The gradients of the quadratic (and the wedge's) shape functions, dN[dim a + i] = dN_a/dξ_i.

void tet10_gradients(const double* x, double* dN) {
  const double L[4] = {1.0 - x[0] - x[1] - x[2], x[0], x[1], x[2]};
  // dL_0 = (-1, -1, -1), dL_i = e_(i-1): dN = f0 dL_0 + sum_i f_i e_(i-1) with f_j = dN/dL_j.
  auto put = [&](int a, double f0, double f1, double f2, double f3) {
    dN[3 * a + 0] = f1 - f0;
    dN[3 * a + 1] = f2 - f0;
    dN[3 * a + 2] = f3 - f0;
  };
  double f[4];
  for (int a = 0; a < 4; ++a) {
    f[0] = f[1] = f[2] = f[3] = 0.0;
    f[a] = 4.0 * L[a] - 1.0;
    put(a, f[0], f[1], f[2], f[3]);
  }
  for (int e = 0; e < 6; ++e) {
    const int i = tet10_edges[e][0], j = tet10_edges[e][1];
    f[0] = f[1] = f[2] = f[3] = 0.0;
    f[i] = 4.0 * L[j];
    f[j] = 4.0 * L[i];
    put(4 + e, f[0], f[1], f[2], f[3]);
  }
}

void hex20_gradients(const double* x, double* dN) {
  for (int a = 0; a < 20; ++a) {
    const double* c = hex20_nodes + 3 * a;
    const double p = 1.0 + c[0] * x[0], q = 1.0 + c[1] * x[1], r = 1.0 + c[2] * x[2];
    double* g = dN + 3 * a;
    if (a < 8) {
      // N = p q r s / 8 with s = c.x - 2: dN/dxi = c0 q r (s + p) / 8, ...
      const double s = c[0] * x[0] + c[1] * x[1] + c[2] * x[2] - 2.0;
      g[0] = 0.125 * c[0] * q * r * (s + p);
      g[1] = 0.125 * c[1] * p * r * (s + q);
      g[2] = 0.125 * c[2] * p * q * (s + r);
    } else if (c[0] == 0.0) {
      const double b = 1.0 - x[0] * x[0];
      g[0] = -0.5 * x[0] * q * r;
      g[1] = 0.25 * b * c[1] * r;
      g[2] = 0.25 * b * q * c[2];
    } else if (c[1] == 0.0) {
      const double b = 1.0 - x[1] * x[1];
      g[0] = 0.25 * c[0] * b * r;
      g[1] = -0.5 * x[1] * p * r;
      g[2] = 0.25 * p * b * c[2];
    } else {
      const double b = 1.0 - x[2] * x[2];
      g[0] = 0.25 * c[0] * q * b;
      g[1] = 0.25 * p * c[1] * b;
      g[2] = -0.5 * x[2] * p * q;
    }
  }
}

void wedge6_gradients(const double* x, double* dN) {
  const double L[3] = {1.0 - x[0] - x[1], x[0], x[1]};
  constexpr double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
  const double lo = 0.5 * (1.0 - x[2]), hi = 0.5 * (1.0 + x[2]);
  for (int a = 0; a < 3; ++a) {
    dN[3 * a + 0] = dL[a][0] * lo;
    dN[3 * a + 1] = dL[a][1] * lo;
    dN[3 * a + 2] = -0.5 * L[a];
    dN[3 * (a + 3) + 0] = dL[a][0] * hi;
    dN[3 * (a + 3) + 1] = dL[a][1] * hi;
    dN[3 * (a + 3) + 2] = 0.5 * L[a];
  }
}

void tri6_gradients(const double* x, double* dN) {
  const double L[3] = {1.0 - x[0] - x[1], x[0], x[1]};
  // dL_0 = (-1, -1), dL_1 = (1, 0), dL_2 = (0, 1).
  double f[3];
  for (int a = 0; a < 3; ++a) {
    f[0] = f[1] = f[2] = 0.0;
    f[a] = 4.0 * L[a] - 1.0;
    dN[2 * a + 0] = f[1] - f[0];
    dN[2 * a + 1] = f[2] - f[0];
  }
  for (int e = 0; e < 3; ++e) {
    const int i = tri6_edges[e][0], j = tri6_edges[e][1];
    f[0] = f[1] = f[2] = 0.0;
    f[i] = 4.0 * L[j];
    f[j] = 4.0 * L[i];
    dN[2 * (3 + e) + 0] = f[1] - f[0];
    dN[2 * (3 + e) + 1] = f[2] - f[0];
  }
}

void quad8_gradients(const double* x, double* dN) {
  for (int a = 0; a < 8; ++a) {
    const double* c = quad8_nodes + 3 * a;
    const double p = 1.0 + c[0] * x[0], q = 1.0 + c[1] * x[1];
    double* g = dN + 2 * a;
    if (a < 4) {
      const double s = c[0] * x[0] + c[1] * x[1] - 1.0;
      g[0] = 0.25 * c[0] * q * (s + p);
      g[1] = 0.25 * c[1] * p * (s + q);
    } else if (c[0] == 0.0) {
      g[0] = -x[0] * q;
      g[1] = 0.5 * (1.0 - x[0] * x[0]) * c[1];
    } else {
      g[0] = 0.5 * c[0] * (1.0 - x[1] * x[1]);
      g[1] = -x[1] * p;
    }
  }
}

}  // namespace

void shape_gradients(CellType type, const double* x, double* dN) {
  switch (type) {
    case CellType::tet4: {
      constexpr double g[12] = {-1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1};
      for (int i = 0; i < 12; ++i) dN[i] = g[i];
      return;
    }
    case CellType::tet10:
      return tet10_gradients(x, dN);
    case CellType::hex8:
      for (int a = 0; a < 8; ++a) {
        const double* c = hex_nodes + 3 * a;
        const double p = 1.0 + c[0] * x[0], q = 1.0 + c[1] * x[1], r = 1.0 + c[2] * x[2];
        dN[3 * a + 0] = 0.125 * c[0] * q * r;
        dN[3 * a + 1] = 0.125 * p * c[1] * r;
        dN[3 * a + 2] = 0.125 * p * q * c[2];
      }
      return;
    case CellType::hex20:
      return hex20_gradients(x, dN);
    case CellType::wedge6:
      return wedge6_gradients(x, dN);
    case CellType::tri3: {
      constexpr double g[6] = {-1, -1, 1, 0, 0, 1};
      for (int i = 0; i < 6; ++i) dN[i] = g[i];
      return;
    }
    case CellType::tri6:
      return tri6_gradients(x, dN);
    case CellType::quad4:
      for (int a = 0; a < 4; ++a) {
        const double* c = quad_nodes + 3 * a;
        dN[2 * a + 0] = 0.25 * c[0] * (1.0 + c[1] * x[1]);
        dN[2 * a + 1] = 0.25 * (1.0 + c[0] * x[0]) * c[1];
      }
      return;
    case CellType::quad8:
      return quad8_gradients(x, dN);
  }
}

namespace {

std::unique_ptr<ReferenceTable> build_table(CellType type, const QuadratureRule& rule) {
  auto t = std::make_unique<ReferenceTable>();
  t->type = type;
  t->degree = rule.degree;
  t->dim = cell_dim(type);
  t->n_nodes = cell_n_nodes(type);
  t->n_points = rule.size();
  t->weights = rule.weights;
  t->points = rule.points;
  const int nn = t->n_nodes, np = t->n_points, dim = t->dim;
  t->N.resize(static_cast<std::size_t>(np) * nn);
  t->dN.resize(static_cast<std::size_t>(np) * nn * dim);
  for (int q = 0; q < np; ++q) {
    shape_values(type, t->points[q].data(), &t->N[static_cast<std::size_t>(q) * nn]);
    shape_gradients(type, t->points[q].data(), &t->dN[static_cast<std::size_t>(q) * nn * dim]);
  }

  // Extrapolation: fit in the span of the corner element's shape functions, evaluate at the nodes.
  const CellType lin = cell_linear(type);
  const int nc = cell_n_nodes(lin);
  t->extrapolation = Eigen::MatrixXd::Constant(nn, np, 1.0 / np);  // the mean: fallback
  if (np >= nc) {
    Eigen::MatrixXd M(np, nc);  // M(q, i) = N_i^lin(point q)
    double row[8];              // corner cells have at most 8 nodes
    for (int q = 0; q < np; ++q) {
      shape_values(lin, t->points[q].data(), row);
      for (int i = 0; i < nc; ++i) M(q, i) = row[i];
    }
    Eigen::MatrixXd L(nn, nc);  // L(a, i) = N_i^lin(node a)
    const double* xn = node_coordinates(type);
    for (int a = 0; a < nn; ++a) {
      shape_values(lin, xn + 3 * a, row);
      for (int i = 0; i < nc; ++i) L(a, i) = row[i];
    }
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(M);
    if (cod.rank() == nc) t->extrapolation = L * cod.solve(Eigen::MatrixXd::Identity(np, np));
    if (lin != type) {
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(np, nn);  // A(q, a): point q's weight of node a
      if (type == CellType::hex20) {
        Eigen::MatrixXd Nq(np, nn);
        for (int q = 0; q < np; ++q)
          for (int a = 0; a < nn; ++a) Nq(q, a) = t->N[static_cast<std::size_t>(q) * nn + a];
        const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(t->weights.data(), np);
        const Eigen::MatrixXd G = M.transpose() * w.asDiagonal() * M;
        A = M * G.ldlt().solve(M.transpose() * w.asDiagonal() * Nq);
      } else {
        A.leftCols(nc) = M;
      }
      t->N_linear_temperature.resize(static_cast<std::size_t>(np) * nn);
      for (int q = 0; q < np; ++q)
        for (int a = 0; a < nn; ++a)
          t->N_linear_temperature[static_cast<std::size_t>(q) * nn + a] = A(q, a);
    }
  }
  return t;
}

constexpr int n_cell_types = 9;
constexpr int max_cached_degree = 32;

std::mutex table_mutex;
std::vector<std::unique_ptr<ReferenceTable>> table_storage;  // guarded by table_mutex
std::atomic<const ReferenceTable*> table_cache[n_cell_types][max_cached_degree + 1];

}  // namespace

const ReferenceTable& reference_table(CellType type, int degree) {
  const int t = static_cast<int>(type);
  if (t < 0 || t >= n_cell_types) throw std::invalid_argument("reference_table: unknown cell type");
  const bool cacheable = degree >= 0 && degree <= max_cached_degree;
  if (cacheable)
    if (const ReferenceTable* p = table_cache[t][degree].load(std::memory_order_acquire)) return *p;

  const QuadratureRule& rule = quadrature(type, degree);  // throws for unavailable degrees
  std::lock_guard lock(table_mutex);
  if (cacheable)
    if (const ReferenceTable* p = table_cache[t][degree].load(std::memory_order_relaxed)) return *p;
  // Degrees that map to the same rule share one table, keyed by the rule's degree.
  HENCKY_VERIFY(rule.degree <= max_cached_degree, "reference_table: rule degree too high");
  const ReferenceTable* p = table_cache[t][rule.degree].load(std::memory_order_relaxed);
  if (!p) {
    table_storage.push_back(build_table(type, rule));
    p = table_storage.back().get();
    table_cache[t][rule.degree].store(p, std::memory_order_release);
  }
  if (cacheable) table_cache[t][degree].store(p, std::memory_order_release);
  return *p;
}

const ReferenceTable& reference_table(CellType type) {
  return reference_table(type, default_degree(type));
}

}  // namespace hencky
