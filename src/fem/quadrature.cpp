// Quadrature rules on the reference domains. The point/weight tables below were derived in
// 50-digit arithmetic (mpmath): Gauss-Legendre from the roots of P_n; the symmetric simplex rules
// by solving their moment equations (exact monomial integrals of the barycentric coordinates) for
// the orbit parameters, starting from the published values, and checking every monomial up to the
// degree to 1e-40. Each table is printed to 21 significant digits.
#include "fem/quadrature.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace hencky {
namespace {

struct Point {
  double x, y, z, w;
};

// clang-format off
// Gauss-Legendre on [-1, 1], points ascending
constexpr double gauss_x[5][5] = {
    {0.0},
    {-5.77350269189625764509e-1, 5.77350269189625764509e-1},
    {-7.74596669241483377036e-1, 0.0, 7.74596669241483377036e-1},
    {-8.61136311594052575224e-1, -3.39981043584856264803e-1, 3.39981043584856264803e-1, 8.61136311594052575224e-1},
    {-9.06179845938663992798e-1, -5.38469310105683091036e-1, 0.0, 5.38469310105683091036e-1, 9.06179845938663992798e-1},
};
constexpr double gauss_w[5][5] = {
    {2.00000000000000000000},
    {1.00000000000000000000, 1.00000000000000000000},
    {5.55555555555555555556e-1, 8.88888888888888888889e-1, 5.55555555555555555556e-1},
    {3.47854845137453857373e-1, 6.52145154862546142627e-1, 6.52145154862546142627e-1, 3.47854845137453857373e-1},
    {2.36926885056189087514e-1, 4.78628670499366468041e-1, 5.68888888888888888889e-1, 4.78628670499366468041e-1, 2.36926885056189087514e-1},
};
// triangle, 1 point, degree 1: centroid
constexpr Point tri_1[] = {
    {3.33333333333333333333e-1, 3.33333333333333333333e-1, 0.0, 5.00000000000000000000e-1},
};
// triangle, 3 points, degree 2 (Strang-Fix): point q near vertex q
constexpr Point tri_3[] = {
    {1.66666666666666666667e-1, 1.66666666666666666667e-1, 0.0, 1.66666666666666666667e-1},
    {6.66666666666666666667e-1, 1.66666666666666666667e-1, 0.0, 1.66666666666666666667e-1},
    {1.66666666666666666667e-1, 6.66666666666666666667e-1, 0.0, 1.66666666666666666667e-1},
};
// triangle, 6 points, degree 4 (Dunavant): two S21 orbits, solved from the moment equations
constexpr Point tri_6[] = {
    {4.45948490915964886318e-1, 4.45948490915964886318e-1, 0.0, 1.11690794839005732848e-1},
    {1.08103018168070227363e-1, 4.45948490915964886318e-1, 0.0, 1.11690794839005732848e-1},
    {4.45948490915964886318e-1, 1.08103018168070227363e-1, 0.0, 1.11690794839005732848e-1},
    {9.15762135097707434596e-2, 9.15762135097707434596e-2, 0.0, 5.49758718276609338192e-2},
    {8.16847572980458513081e-1, 9.15762135097707434596e-2, 0.0, 5.49758718276609338192e-2},
    {9.15762135097707434596e-2, 8.16847572980458513081e-1, 0.0, 5.49758718276609338192e-2},
};
// triangle, 7 points, degree 5 (Radon): centroid 9/80, S21 a=(6-+sqrt15)/21 with weights (155-+sqrt15)/2400
constexpr Point tri_7[] = {
    {3.33333333333333333333e-1, 3.33333333333333333333e-1, 0.0, 1.12500000000000000000e-1},
    {1.01286507323456338801e-1, 1.01286507323456338801e-1, 0.0, 6.29695902724135762978e-2},
    {7.97426985353087322398e-1, 1.01286507323456338801e-1, 0.0, 6.29695902724135762978e-2},
    {1.01286507323456338801e-1, 7.97426985353087322398e-1, 0.0, 6.29695902724135762978e-2},
    {4.70142064105115089770e-1, 4.70142064105115089770e-1, 0.0, 6.61970763942530903688e-2},
    {5.97158717897698204591e-2, 4.70142064105115089770e-1, 0.0, 6.61970763942530903688e-2},
    {4.70142064105115089770e-1, 5.97158717897698204591e-2, 0.0, 6.61970763942530903688e-2},
};
// triangle, 12 points, degree 6 (Dunavant): two S21 orbits and one S111 orbit
constexpr Point tri_12[] = {
    {6.30890144915022283403e-2, 6.30890144915022283403e-2, 0.0, 2.54224531851034084605e-2},
    {8.73821971016995543319e-1, 6.30890144915022283403e-2, 0.0, 2.54224531851034084605e-2},
    {6.30890144915022283403e-2, 8.73821971016995543319e-1, 0.0, 2.54224531851034084605e-2},
    {2.49286745170910421292e-1, 2.49286745170910421292e-1, 0.0, 5.83931378631896830126e-2},
    {5.01426509658179157417e-1, 2.49286745170910421292e-1, 0.0, 5.83931378631896830126e-2},
    {2.49286745170910421292e-1, 5.01426509658179157417e-1, 0.0, 5.83931378631896830126e-2},
    {3.10352451033784405417e-1, 5.31450498448169473532e-2, 0.0, 4.14255378091867875968e-2},
    {5.31450498448169473532e-2, 3.10352451033784405417e-1, 0.0, 4.14255378091867875968e-2},
    {6.36502499121398647230e-1, 5.31450498448169473532e-2, 0.0, 4.14255378091867875968e-2},
    {5.31450498448169473532e-2, 6.36502499121398647230e-1, 0.0, 4.14255378091867875968e-2},
    {6.36502499121398647230e-1, 3.10352451033784405417e-1, 0.0, 4.14255378091867875968e-2},
    {3.10352451033784405417e-1, 6.36502499121398647230e-1, 0.0, 4.14255378091867875968e-2},
};
// tetrahedron, 1 point, degree 1: centroid
constexpr Point tet_1[] = {
    {2.50000000000000000000e-1, 2.50000000000000000000e-1, 2.50000000000000000000e-1, 1.66666666666666666667e-1},
};
// tetrahedron, 4 points, degree 2: S31 a=(5-sqrt5)/20, weights 1/24; point q near vertex q
constexpr Point tet_4[] = {
    {1.38196601125010515180e-1, 1.38196601125010515180e-1, 1.38196601125010515180e-1, 4.16666666666666666667e-2},
    {5.85410196624968454461e-1, 1.38196601125010515180e-1, 1.38196601125010515180e-1, 4.16666666666666666667e-2},
    {1.38196601125010515180e-1, 5.85410196624968454461e-1, 1.38196601125010515180e-1, 4.16666666666666666667e-2},
    {1.38196601125010515180e-1, 1.38196601125010515180e-1, 5.85410196624968454461e-1, 4.16666666666666666667e-2},
};
// tetrahedron, 14 points, degree 5 (Walkington; Keast): two S31 orbits and one S22 orbit
constexpr Point tet_14[] = {
    {9.27352503108912264023e-2, 9.27352503108912264023e-2, 9.27352503108912264023e-2, 1.22488405193936582573e-2},
    {7.21794249067326320793e-1, 9.27352503108912264023e-2, 9.27352503108912264023e-2, 1.22488405193936582573e-2},
    {9.27352503108912264023e-2, 7.21794249067326320793e-1, 9.27352503108912264023e-2, 1.22488405193936582573e-2},
    {9.27352503108912264023e-2, 9.27352503108912264023e-2, 7.21794249067326320793e-1, 1.22488405193936582573e-2},
    {3.10885919263300609797e-1, 3.10885919263300609797e-1, 3.10885919263300609797e-1, 1.87813209530026417999e-2},
    {6.73422422100981706080e-2, 3.10885919263300609797e-1, 3.10885919263300609797e-1, 1.87813209530026417999e-2},
    {3.10885919263300609797e-1, 6.73422422100981706080e-2, 3.10885919263300609797e-1, 1.87813209530026417999e-2},
    {3.10885919263300609797e-1, 3.10885919263300609797e-1, 6.73422422100981706080e-2, 1.87813209530026417999e-2},
    {4.54496295874350350508e-1, 4.55037041256496494919e-2, 4.55037041256496494919e-2, 7.09100346284691107301e-3},
    {4.55037041256496494919e-2, 4.54496295874350350508e-1, 4.55037041256496494919e-2, 7.09100346284691107301e-3},
    {4.55037041256496494919e-2, 4.55037041256496494919e-2, 4.54496295874350350508e-1, 7.09100346284691107301e-3},
    {4.54496295874350350508e-1, 4.54496295874350350508e-1, 4.55037041256496494919e-2, 7.09100346284691107301e-3},
    {4.54496295874350350508e-1, 4.55037041256496494919e-2, 4.54496295874350350508e-1, 7.09100346284691107301e-3},
    {4.55037041256496494919e-2, 4.54496295874350350508e-1, 4.54496295874350350508e-1, 7.09100346284691107301e-3},
};
// clang-format on

template <std::size_t N>
QuadratureRule from_table(int degree, const Point (&table)[N]) {
  QuadratureRule r;
  r.degree = degree;
  r.points.reserve(N);
  r.weights.reserve(N);
  for (const Point& p : table) {
    r.points.push_back({p.x, p.y, p.z});
    r.weights.push_back(p.w);
  }
  return r;
}

/// n^dim Gauss rule on [-1, 1]^dim, first coordinate fastest.
QuadratureRule gauss_tensor(int n, int dim) {
  QuadratureRule r;
  r.degree = 2 * n - 1;
  const int nz = dim == 3 ? n : 1;
  const int ny = dim >= 2 ? n : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < n; ++i) {
        double w = gauss_w[n - 1][i];
        std::array<double, 3> p{gauss_x[n - 1][i], 0.0, 0.0};
        if (dim >= 2) {
          p[1] = gauss_x[n - 1][j];
          w *= gauss_w[n - 1][j];
        }
        if (dim == 3) {
          p[2] = gauss_x[n - 1][k];
          w *= gauss_w[n - 1][k];
        }
        r.points.push_back(p);
        r.weights.push_back(w);
      }
  return r;
}

/// Triangle rule x n-point Gauss in zeta; zeta slowest (the first tri.size() points are nearest
/// the face zeta = -1).
QuadratureRule wedge_rule(const QuadratureRule& tri, int n) {
  QuadratureRule r;
  r.degree = std::min(tri.degree, 2 * n - 1);
  for (int k = 0; k < n; ++k)
    for (int q = 0; q < tri.size(); ++q) {
      r.points.push_back({tri.points[q][0], tri.points[q][1], gauss_x[n - 1][k]});
      r.weights.push_back(tri.weights[q] * gauss_w[n - 1][k]);
    }
  return r;
}

enum Domain { line, quadrilateral, hexahedron, triangle, tetrahedron, wedge, n_domains };

Domain domain_of(CellType t) {
  switch (t) {
    case CellType::tet4:
    case CellType::tet10:
      return tetrahedron;
    case CellType::hex8:
    case CellType::hex20:
      return hexahedron;
    case CellType::wedge6:
      return wedge;
    case CellType::tri3:
    case CellType::tri6:
      return triangle;
    case CellType::quad4:
    case CellType::quad8:
      return quadrilateral;
  }
  throw std::invalid_argument("quadrature: unknown cell type");
}

/// All rules, per domain in increasing size (and degree).
struct Rules {
  std::vector<QuadratureRule> by_domain[n_domains];

  Rules() {
    for (int n = 1; n <= 5; ++n) {
      by_domain[line].push_back(gauss_tensor(n, 1));
      by_domain[quadrilateral].push_back(gauss_tensor(n, 2));
      by_domain[hexahedron].push_back(gauss_tensor(n, 3));
    }
    auto& tri = by_domain[triangle];
    tri.push_back(from_table(1, tri_1));
    tri.push_back(from_table(2, tri_3));
    tri.push_back(from_table(4, tri_6));
    tri.push_back(from_table(5, tri_7));
    tri.push_back(from_table(6, tri_12));
    auto& tet = by_domain[tetrahedron];
    tet.push_back(from_table(1, tet_1));
    tet.push_back(from_table(2, tet_4));
    tet.push_back(from_table(5, tet_14));
    // Wedge of degree d: smallest triangle rule of degree >= d x ceil((d + 1) / 2) Gauss points.
    for (int d = 1; d <= tri.back().degree; ++d) {
      const QuadratureRule* t = nullptr;
      for (const auto& r : tri)
        if (r.degree >= d) {
          t = &r;
          break;
        }
      by_domain[wedge].push_back(wedge_rule(*t, (d + 2) / 2));
    }
  }
};

const Rules& rules() {
  static const Rules r;
  return r;
}

}  // namespace

const QuadratureRule& quadrature(CellType type, int degree) {
  const auto& list = rules().by_domain[domain_of(type)];
  if (degree >= 0)
    for (const auto& r : list)
      if (r.degree >= degree) return r;
  throw std::invalid_argument("no quadrature rule of degree " + std::to_string(degree) +
                              " for the " + std::string(cell_name(type)) + " (available: up to " +
                              std::to_string(list.back().degree) + ")");
}

int max_quadrature_degree(CellType type) {
  return rules().by_domain[domain_of(type)].back().degree;
}

const QuadratureRule& gauss_legendre(int n_points) {
  if (n_points < 1 || n_points > 5)
    throw std::invalid_argument("gauss_legendre: " + std::to_string(n_points) +
                                " points requested, 1 to 5 available");
  return rules().by_domain[line][n_points - 1];
}

int default_degree(CellType type) {
  switch (type) {
    case CellType::tet4:
      return 1;
    case CellType::tet10:
      return 2;
    case CellType::hex8:
      return 3;
    case CellType::hex20:
      return 5;
    case CellType::wedge6:
      return 2;
    case CellType::tri3:
      return 2;
    case CellType::tri6:
      return 4;
    case CellType::quad4:
      return 3;
    case CellType::quad8:
      return 5;
  }
  throw std::invalid_argument("default_degree: unknown cell type");
}

}  // namespace hencky
