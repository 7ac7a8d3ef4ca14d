// Reference elements and quadrature: shape functions against Gmsh's own reference cells and basis
// functions, exactness of every quadrature rule, and the precomputed reference tables.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "fem/cell_type.hpp"
#include "fem/quadrature.hpp"
#include "fem/reference_element.hpp"

using namespace hencky;

// Gmsh 4.8 leaks the face closures it builds for the prism basis (ClosureGen::getFaceClosurePrism);
// keep LeakSanitizer (HENCKY_SANITIZE builds) quiet about that one. Weak, so that a project-wide
// definition elsewhere wins; unused without the sanitizer. Visible: gcc's shared sanitizer
// runtime looks it up in the program's exported symbols.
extern "C" __attribute__((weak, visibility("default"))) const char* __lsan_default_suppressions() {
  return "leak:ClosureGen::getFaceClosurePrism\n";
}

namespace {

constexpr CellType all_types[] = {CellType::tet4,  CellType::tet10,  CellType::hex8,
                                  CellType::hex20, CellType::wedge6, CellType::tri3,
                                  CellType::tri6,  CellType::quad4,  CellType::quad8};
/// One cell per reference domain.
constexpr CellType domain_types[] = {CellType::tet4, CellType::hex8, CellType::wedge6,
                                     CellType::tri3, CellType::quad4};

int gmsh_type(CellType t) {
  switch (t) {
    case CellType::tet4:
      return 4;
    case CellType::tet10:
      return 11;
    case CellType::hex8:
      return 5;
    case CellType::hex20:
      return 17;
    case CellType::wedge6:
      return 6;
    case CellType::tri3:
      return 2;
    case CellType::tri6:
      return 9;
    case CellType::quad4:
      return 3;
    case CellType::quad8:
      return 16;
  }
  return 0;
}

std::string name(CellType t) {
  return std::string(cell_name(t));
}

bool is_simplex(CellType t) {
  return t == CellType::tet4 || t == CellType::tet10 || t == CellType::tri3 || t == CellType::tri6;
}

double factorial(int n) {
  double f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

/// Exact integral of xi^i over [-1, 1].
double line_integral(int i) {
  return i % 2 ? 0.0 : 2.0 / (i + 1);
}

/// Exact integral of xi^i eta^j zeta^k over the reference domain of t (k = 0 in 2D).
double exact_integral(CellType t, int i, int j, int k) {
  switch (t) {
    case CellType::tet4:
    case CellType::tet10:
      return factorial(i) * factorial(j) * factorial(k) / factorial(i + j + k + 3);
    case CellType::hex8:
    case CellType::hex20:
      return line_integral(i) * line_integral(j) * line_integral(k);
    case CellType::wedge6:
      return factorial(i) * factorial(j) / factorial(i + j + 2) * line_integral(k);
    case CellType::tri3:
    case CellType::tri6:
      return factorial(i) * factorial(j) / factorial(i + j + 2);
    case CellType::quad4:
    case CellType::quad8:
      return line_integral(i) * line_integral(j);
  }
  return 0.0;
}

double reference_volume(CellType t) {
  return exact_integral(t, 0, 0, 0);
}

/// Strictly inside the reference domain (with margin m).
bool inside(CellType t, const std::array<double, 3>& x, double m = 0.0) {
  const int dim = cell_dim(t);
  switch (t) {
    case CellType::tet4:
    case CellType::tet10:
      return x[0] > m && x[1] > m && x[2] > m && x[0] + x[1] + x[2] < 1 - m;
    case CellType::wedge6:
      return x[0] > m && x[1] > m && x[0] + x[1] < 1 - m && std::abs(x[2]) < 1 - m;
    case CellType::tri3:
    case CellType::tri6:
      return x[0] > m && x[1] > m && x[0] + x[1] < 1 - m && x[2] == 0.0;
    default:
      for (int k = 0; k < 3; ++k)
        if (k < dim ? std::abs(x[k]) >= 1 - m : x[k] != 0.0) return false;
      return true;
  }
}

/// Random points well inside the reference domain.
std::vector<std::array<double, 3>> random_points(CellType t, int n, unsigned seed = 12345) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0), u11(-1.0, 1.0);
  const int dim = cell_dim(t);
  std::vector<std::array<double, 3>> pts;
  while (static_cast<int>(pts.size()) < n) {
    std::array<double, 3> x{0, 0, 0};
    for (int k = 0; k < dim; ++k) {
      const bool unit = is_simplex(t) || (t == CellType::wedge6 && k < 2);
      x[k] = unit ? u01(gen) : u11(gen);
    }
    if (inside(t, x, 0.02)) pts.push_back(x);
  }
  return pts;
}

double monomial(const std::array<double, 3>& x, int i, int j, int k) {
  return std::pow(x[0], i) * std::pow(x[1], j) * std::pow(x[2], k);
}

/// Largest |rule - exact| over all monomials of total degree exactly d.
double worst_error_at_degree(CellType t, const QuadratureRule& r, int d) {
  const int dim = cell_dim(t);
  double worst = 0.0;
  for (int i = 0; i <= d; ++i)
    for (int j = 0; j <= d - i; ++j) {
      const int k = d - i - j;
      if (dim == 2 && k != 0) continue;
      double q = 0.0;
      for (int p = 0; p < r.size(); ++p) q += r.weights[p] * monomial(r.points[p], i, j, k);
      worst = std::max(worst, std::abs(q - exact_integral(t, i, j, k)));
    }
  return worst;
}

struct GmshSession {
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Quadrature

TEST(QuadratureRules, ExactForEveryMonomialUpToItsDegree) {
  for (CellType t : domain_types) {
    SCOPED_TRACE(name(t));
    const int dim = cell_dim(t);
    const double vol = reference_volume(t);
    const double tol = 2e-15 * std::max(1.0, vol);
    std::set<const QuadratureRule*> seen;
    for (int d = 0; d <= max_quadrature_degree(t); ++d) {
      SCOPED_TRACE("degree " + std::to_string(d));
      const QuadratureRule& r = quadrature(t, d);
      EXPECT_GE(r.degree, d);
      if (!seen.insert(&r).second) continue;  // already checked
      ASSERT_EQ(r.points.size(), r.weights.size());
      ASSERT_GT(r.size(), 0);
      double sum = 0.0;
      for (int q = 0; q < r.size(); ++q) {
        EXPECT_GT(r.weights[q], 0.0);
        EXPECT_TRUE(inside(t, r.points[q])) << "point " << q;
        if (dim == 2) {
          EXPECT_EQ(r.points[q][2], 0.0);
        }
        sum += r.weights[q];
      }
      EXPECT_NEAR(sum, vol, tol);
      for (int e = 0; e <= r.degree; ++e)
        EXPECT_LT(worst_error_at_degree(t, r, e), tol) << "monomials of degree " << e;
      // Not exact one degree higher: the stated degree is the true one.
      EXPECT_GT(worst_error_at_degree(t, r, r.degree + 1), 1e-8)
          << "exact at degree " << r.degree + 1;
    }
  }
}

TEST(QuadratureRules, ProvidedRulesAndSizes) {
  struct Expect {
    CellType type;
    int degree, points, rule_degree;
  };
  const Expect table[] = {
      {CellType::tet4, 1, 1, 1},    {CellType::tet4, 2, 4, 2},    {CellType::tet4, 3, 14, 5},
      {CellType::tet4, 4, 14, 5},   {CellType::tet4, 5, 14, 5},   {CellType::tri3, 1, 1, 1},
      {CellType::tri3, 2, 3, 2},    {CellType::tri3, 3, 6, 4},    {CellType::tri3, 4, 6, 4},
      {CellType::tri3, 5, 7, 5},    {CellType::tri3, 6, 12, 6},   {CellType::quad4, 1, 1, 1},
      {CellType::quad4, 3, 4, 3},   {CellType::quad4, 5, 9, 5},   {CellType::quad4, 9, 25, 9},
      {CellType::hex8, 1, 1, 1},    {CellType::hex8, 3, 8, 3},    {CellType::hex8, 5, 27, 5},
      {CellType::hex8, 7, 64, 7},   {CellType::hex8, 9, 125, 9},  {CellType::wedge6, 1, 1, 1},
      {CellType::wedge6, 2, 6, 2},  {CellType::wedge6, 3, 12, 3}, {CellType::wedge6, 4, 18, 4},
      {CellType::wedge6, 5, 21, 5}, {CellType::wedge6, 6, 48, 6},
  };
  for (const auto& e : table) {
    SCOPED_TRACE(name(e.type) + ", degree " + std::to_string(e.degree));
    const QuadratureRule& r = quadrature(e.type, e.degree);
    EXPECT_EQ(r.size(), e.points);
    EXPECT_EQ(r.degree, e.rule_degree);
  }
  EXPECT_EQ(max_quadrature_degree(CellType::tet10), 5);
  EXPECT_EQ(max_quadrature_degree(CellType::hex20), 9);
  EXPECT_EQ(max_quadrature_degree(CellType::wedge6), 6);
  EXPECT_EQ(max_quadrature_degree(CellType::tri6), 6);
  EXPECT_EQ(max_quadrature_degree(CellType::quad8), 9);
  // Cells on the same domain share the rules.
  EXPECT_EQ(&quadrature(CellType::tet4, 2), &quadrature(CellType::tet10, 2));
  EXPECT_EQ(&quadrature(CellType::hex8, 5), &quadrature(CellType::hex20, 5));
  EXPECT_EQ(&quadrature(CellType::quad4, 3), &quadrature(CellType::quad8, 3));
}

TEST(QuadratureRules, DefaultDegrees) {
  struct Expect {
    CellType type;
    int degree, points;
  };
  const Expect table[] = {
      {CellType::tet4, 1, 1},   {CellType::tet10, 2, 4},  {CellType::hex8, 3, 8},
      {CellType::hex20, 5, 27}, {CellType::wedge6, 2, 6}, {CellType::tri3, 2, 3},
      {CellType::tri6, 4, 6},   {CellType::quad4, 3, 4},  {CellType::quad8, 5, 9}};
  for (const auto& e : table) {
    SCOPED_TRACE(name(e.type));
    EXPECT_EQ(default_degree(e.type), e.degree);
    EXPECT_EQ(quadrature(e.type, default_degree(e.type)).size(), e.points);
  }
}

TEST(QuadratureRules, GaussLegendre) {
  for (int n = 1; n <= 5; ++n) {
    SCOPED_TRACE(std::to_string(n) + " points");
    const QuadratureRule& r = gauss_legendre(n);
    ASSERT_EQ(r.size(), n);
    EXPECT_EQ(r.degree, 2 * n - 1);
    for (int d = 0; d <= 2 * n; ++d) {
      double q = 0.0;
      for (int p = 0; p < n; ++p) {
        q += r.weights[p] * std::pow(r.points[p][0], d);
        EXPECT_EQ(r.points[p][1], 0.0);
        EXPECT_EQ(r.points[p][2], 0.0);
      }
      if (d < 2 * n) {
        EXPECT_NEAR(q, line_integral(d), 1e-15) << "xi^" << d;
      } else {
        EXPECT_GT(std::abs(q - line_integral(d)), 1e-6) << "exact at degree " << d;
      }
    }
  }
  EXPECT_THROW(gauss_legendre(0), std::invalid_argument);
  EXPECT_THROW(gauss_legendre(6), std::invalid_argument);
}

TEST(QuadratureRules, ThrowsWhenUnavailable) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    EXPECT_THROW(quadrature(t, max_quadrature_degree(t) + 1), std::invalid_argument);
    EXPECT_THROW(quadrature(t, -1), std::invalid_argument);
    EXPECT_THROW(reference_table(t, max_quadrature_degree(t) + 1), std::invalid_argument);
    EXPECT_NO_THROW(quadrature(t, 1));
  }
}

// ---------------------------------------------------------------------------------------------
// Shape functions

TEST(ReferenceElement, PartitionOfUnity) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int n = cell_n_nodes(t), dim = cell_dim(t);
    for (const auto& x : random_points(t, 20)) {
      double N[20], dN[60];
      shape_values(t, x.data(), N);
      shape_gradients(t, x.data(), dN);
      double s = 0.0, ds[3] = {0, 0, 0};
      for (int a = 0; a < n; ++a) {
        s += N[a];
        for (int k = 0; k < dim; ++k) ds[k] += dN[a * dim + k];
      }
      EXPECT_NEAR(s, 1.0, 1e-14);
      for (int k = 0; k < dim; ++k) EXPECT_NEAR(ds[k], 0.0, 1e-14);
    }
  }
}

TEST(ReferenceElement, ReproducesTheNaturalCoordinates) {
  // Isoparametric completeness: sum_a N_a(x) x_a = x and sum_a dN_a/dxi_k x_a = e_k.
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int n = cell_n_nodes(t), dim = cell_dim(t);
    const double* xn = node_coordinates(t);
    for (const auto& x : random_points(t, 10)) {
      double N[20], dN[60];
      shape_values(t, x.data(), N);
      shape_gradients(t, x.data(), dN);
      for (int i = 0; i < dim; ++i) {
        double v = 0.0;
        for (int a = 0; a < n; ++a) v += N[a] * xn[3 * a + i];
        EXPECT_NEAR(v, x[i], 1e-14);
        for (int k = 0; k < dim; ++k) {
          double g = 0.0;
          for (int a = 0; a < n; ++a) g += dN[a * dim + k] * xn[3 * a + i];
          EXPECT_NEAR(g, i == k ? 1.0 : 0.0, 1e-14);
        }
      }
    }
  }
}

TEST(ReferenceElement, KroneckerAtNodes) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int n = cell_n_nodes(t);
    const double* xn = node_coordinates(t);
    for (int b = 0; b < n; ++b) {
      double N[20];
      shape_values(t, xn + 3 * b, N);
      for (int a = 0; a < n; ++a)
        EXPECT_NEAR(N[a], a == b ? 1.0 : 0.0, 1e-15) << "N_" << a << "(node " << b << ")";
    }
  }
}

TEST(ReferenceElement, GradientsMatchFiniteDifferences) {
  const double h = 1e-6;
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int n = cell_n_nodes(t), dim = cell_dim(t);
    for (const auto& x : random_points(t, 20, 777)) {
      double dN[60];
      shape_gradients(t, x.data(), dN);
      for (int k = 0; k < dim; ++k) {
        auto xp = x, xm = x;
        xp[k] += h;
        xm[k] -= h;
        double Np[20], Nm[20];
        shape_values(t, xp.data(), Np);
        shape_values(t, xm.data(), Nm);
        for (int a = 0; a < n; ++a)
          EXPECT_NEAR(dN[a * dim + k], (Np[a] - Nm[a]) / (2 * h), 1e-8)
              << "dN_" << a << "/dxi_" << k;
      }
    }
  }
}

TEST(ReferenceElement, NodeCoordinatesMatchGmsh) {
  GmshSession session;
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    std::string gname;
    int dim = 0, order = 0, n_nodes = 0, n_primary = 0;
    std::vector<double> coord;
    gmsh::model::mesh::getElementProperties(gmsh_type(t), gname, dim, order, n_nodes, coord,
                                            n_primary);
    ASSERT_EQ(dim, cell_dim(t));
    ASSERT_EQ(n_nodes, cell_n_nodes(t));
    EXPECT_EQ(n_primary, cell_n_corners(t));
    ASSERT_EQ(static_cast<int>(coord.size()), n_nodes * dim);
    const double* xn = node_coordinates(t);
    for (int a = 0; a < n_nodes; ++a)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(xn[3 * a + k], k < dim ? coord[a * dim + k] : 0.0, 1e-14)
            << "node " << a << ", coordinate " << k;
  }
}

TEST(ReferenceElement, ShapeFunctionsMatchGmsh) {
  // Gmsh's Lagrange basis of each element type (serendipity for the 20-node hexahedron and the
  // 8-node quadrilateral) at random points, values and natural gradients.
  GmshSession session;
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int n = cell_n_nodes(t), dim = cell_dim(t);
    const auto pts = random_points(t, 10, 99);
    std::vector<double> local;
    for (const auto& x : pts) local.insert(local.end(), x.begin(), x.end());
    int n_comp = 0, n_orient = 0;
    std::vector<double> values, grads;
    gmsh::model::mesh::getBasisFunctions(gmsh_type(t), local, "Lagrange", n_comp, values, n_orient);
    ASSERT_EQ(n_comp, 1);
    ASSERT_EQ(values.size(), pts.size() * n);
    int n_gcomp = 0;
    gmsh::model::mesh::getBasisFunctions(gmsh_type(t), local, "GradLagrange", n_gcomp, grads,
                                         n_orient);
    ASSERT_EQ(n_gcomp, 3);
    ASSERT_EQ(grads.size(), pts.size() * n * 3);
    for (std::size_t p = 0; p < pts.size(); ++p) {
      double N[20], dN[60];
      shape_values(t, pts[p].data(), N);
      shape_gradients(t, pts[p].data(), dN);
      for (int a = 0; a < n; ++a) {
        EXPECT_NEAR(N[a], values[p * n + a], 1e-12) << "N_" << a;
        for (int k = 0; k < dim; ++k)
          EXPECT_NEAR(dN[a * dim + k], grads[(p * n + a) * 3 + k], 1e-12)
              << "dN_" << a << "/dxi_" << k;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Reference tables

TEST(ReferenceTable, MatchesDirectEvaluation) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    for (int d = 1; d <= max_quadrature_degree(t); ++d) {
      SCOPED_TRACE("degree " + std::to_string(d));
      const ReferenceTable& tab = reference_table(t, d);
      const QuadratureRule& r = quadrature(t, d);
      EXPECT_EQ(tab.type, t);
      EXPECT_EQ(tab.degree, r.degree);
      EXPECT_EQ(tab.dim, cell_dim(t));
      EXPECT_EQ(tab.n_nodes, cell_n_nodes(t));
      ASSERT_EQ(tab.n_points, r.size());
      ASSERT_EQ(tab.weights, r.weights);
      ASSERT_EQ(tab.points, r.points);
      const int n = tab.n_nodes, dim = tab.dim;
      ASSERT_EQ(static_cast<int>(tab.N.size()), tab.n_points * n);
      ASSERT_EQ(static_cast<int>(tab.dN.size()), tab.n_points * n * dim);
      EXPECT_EQ(tab.extrapolation.rows(), n);
      EXPECT_EQ(tab.extrapolation.cols(), tab.n_points);
      for (int q = 0; q < tab.n_points; ++q) {
        double N[20], dN[60];
        shape_values(t, r.points[q].data(), N);
        shape_gradients(t, r.points[q].data(), dN);
        for (int a = 0; a < n; ++a) {
          EXPECT_EQ(tab.N[q * n + a], N[a]);
          for (int k = 0; k < dim; ++k) EXPECT_EQ(tab.dN[(q * n + a) * dim + k], dN[a * dim + k]);
        }
      }
    }
  }
}

TEST(ReferenceTable, ExtrapolationReproducesConstantsAndLinearFields) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const int dim = cell_dim(t);
    const double* xn = node_coordinates(t);
    for (int d = 1; d <= max_quadrature_degree(t); ++d) {
      SCOPED_TRACE("degree " + std::to_string(d));
      const ReferenceTable& tab = reference_table(t, d);
      const auto& E = tab.extrapolation;
      // Constants: every row sums to 1.
      for (int a = 0; a < tab.n_nodes; ++a) EXPECT_NEAR(E.row(a).sum(), 1.0, 1e-12);
      if (tab.n_points < cell_n_corners(t)) {
        // Fewer points than corners: the mean.
        EXPECT_NEAR((E.array() - 1.0 / tab.n_points).abs().maxCoeff(), 0.0, 1e-15);
        continue;
      }
      const double c[4] = {0.7, -1.3, 2.1, 0.4};
      Eigen::VectorXd at_points(tab.n_points);
      for (int q = 0; q < tab.n_points; ++q) {
        at_points[q] = c[0];
        for (int k = 0; k < dim; ++k) at_points[q] += c[k + 1] * tab.points[q][k];
      }
      const Eigen::VectorXd at_nodes = E * at_points;
      for (int a = 0; a < tab.n_nodes; ++a) {
        double f = c[0];
        for (int k = 0; k < dim; ++k) f += c[k + 1] * xn[3 * a + k];
        EXPECT_NEAR(at_nodes[a], f, 1e-12) << "node " << a;
      }
    }
  }
}

TEST(ReferenceTable, ExtrapolationReproducesCornerElementFields) {
  // Any field in the span of the corner element's shape functions (e.g. the bilinear xi*eta on a
  // quadrilateral, the trilinear xi*eta*zeta on a hexahedron) is reproduced at the corners.
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    const ReferenceTable& tab = reference_table(t);
    const CellType lin = cell_linear(t);
    const int nc = cell_n_corners(t);
    if (tab.n_points < nc) continue;
    for (int i = 0; i < nc; ++i) {
      Eigen::VectorXd at_points(tab.n_points);
      for (int q = 0; q < tab.n_points; ++q) {
        double N[8];
        shape_values(lin, tab.points[q].data(), N);
        at_points[q] = N[i];
      }
      const Eigen::VectorXd at_nodes = tab.extrapolation * at_points;
      for (int a = 0; a < nc; ++a) EXPECT_NEAR(at_nodes[a], a == i ? 1.0 : 0.0, 1e-12);
    }
  }
}

TEST(ReferenceTable, Hex8ClassicalExtrapolation) {
  // 2x2x2 Gauss: E(a, q) = prod_k (1 + 3 g_qk x_ak) / 8 (the trilinear interpolation through the
  // Gauss points, evaluated at the corners x_a = +-1 with g = +-1/sqrt(3)).
  const ReferenceTable& tab = reference_table(CellType::hex8);
  ASSERT_EQ(tab.n_points, 8);
  const double* xn = node_coordinates(CellType::hex8);
  for (int a = 0; a < 8; ++a)
    for (int q = 0; q < 8; ++q) {
      double e = 0.125;
      for (int k = 0; k < 3; ++k) e *= 1.0 + 3.0 * tab.points[q][k] * xn[3 * a + k];
      EXPECT_NEAR(tab.extrapolation(a, q), e, 1e-13) << "node " << a << ", point " << q;
    }
}

TEST(ReferenceTable, CachedAndThreadSafe) {
  for (CellType t : all_types) {
    SCOPED_TRACE(name(t));
    EXPECT_EQ(&reference_table(t), &reference_table(t, default_degree(t)));
    EXPECT_EQ(reference_table(t).n_points, quadrature(t, default_degree(t)).size());
  }
  // Degrees served by the same rule share the table.
  EXPECT_EQ(&reference_table(CellType::tet10, 3), &reference_table(CellType::tet10, 5));
  EXPECT_EQ(&reference_table(CellType::tri6, 3), &reference_table(CellType::tri6, 4));
  EXPECT_EQ(&reference_table(CellType::hex20, 4), &reference_table(CellType::hex20, 5));
  EXPECT_NE(&reference_table(CellType::tet4, 2), &reference_table(CellType::tet10, 2));

  // Many threads asking at once through cache slots not filled yet (degree 0 is only asked for
  // here; it maps to the degree-1 rule) all get the same objects.
  constexpr int n_threads = 8;
  std::vector<std::array<const ReferenceTable*, 9>> got(n_threads);
  std::vector<std::thread> threads;
  for (int i = 0; i < n_threads; ++i)
    threads.emplace_back([&got, i] {
      for (int rep = 0; rep < 50; ++rep)
        for (int j = 0; j < 9; ++j) {
          const CellType t = all_types[(j + i) % 9];
          got[i][(j + i) % 9] = &reference_table(t, 0);
        }
    });
  for (auto& th : threads) th.join();
  for (int j = 0; j < 9; ++j) {
    EXPECT_EQ(got[0][j], &reference_table(all_types[j], 1));
    for (int i = 1; i < n_threads; ++i) EXPECT_EQ(got[i][j], got[0][j]);
  }
}
