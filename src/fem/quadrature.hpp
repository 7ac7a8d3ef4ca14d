#pragma once
// Numerical integration on the reference domains of the cells (Gmsh's reference cells):
//   tetrahedron   unit simplex {xi, eta, zeta >= 0, xi + eta + zeta <= 1}   volume 1/6
//   hexahedron    [-1, 1]^3                                                 volume 8
//   wedge         unit triangle (xi, eta) x zeta in [-1, 1]                  volume 1
//   triangle      unit triangle {xi, eta >= 0, xi + eta <= 1}               area 1/2
//   quadrilateral [-1, 1]^2                                                 area 4
// Every rule has positive weights and all its points strictly inside the domain.
//
// Rules provided (points, degree of exactness):
//   line          Gauss-Legendre with n = 1..5 points, degree 2n - 1
//   quadrilateral n x n Gauss, n = 1..5, degree 2n - 1
//   hexahedron    n x n x n Gauss, n = 1..5, degree 2n - 1
//   triangle      1 (deg 1), 3 (deg 2), 6 (deg 4), 7 (deg 5), 12 (deg 6)
//   tetrahedron   1 (deg 1), 4 (deg 2), 14 (deg 5)   (no positive degree-3/4 rule smaller than 14)
//   wedge         triangle rule x Gauss line rule: 1 (deg 1), 6 (deg 2), 12 (deg 3), 18 (deg 4),
//                 21 (deg 5), 48 (deg 6)
// "Degree d" means that every polynomial of total degree <= d is integrated exactly (the
// tensor-product rules do more: every monomial with each exponent <= 2n - 1).
#include <array>
#include <vector>

#include "fem/cell_type.hpp"

namespace hencky {

struct QuadratureRule {
  int degree = 0;  ///< polynomials up to this total degree are integrated exactly
  std::vector<std::array<double, 3>> points;  ///< natural coordinates (unused trailing coords = 0)
  std::vector<double> weights;                ///< one per point; they sum to the reference volume

  int size() const { return static_cast<int>(weights.size()); }
};

/// Smallest rule of this cell's reference domain exact for the given degree (degree >= 1;
/// 0 is accepted and gives the degree-1 rule). Cells sharing a domain (tet4/tet10, ...) share the
/// rules. The reference stays valid for the life of the program; safe to call concurrently.
/// Throws std::invalid_argument when degree < 0 or > max_quadrature_degree(type).
const QuadratureRule& quadrature(CellType type, int degree);

/// Highest degree quadrature() can provide for this cell's reference domain.
int max_quadrature_degree(CellType type);

/// Gauss-Legendre rule with n_points = 1..5 points on [-1, 1] (points[q][0]; degree 2n - 1).
/// Throws std::invalid_argument for other counts.
const QuadratureRule& gauss_legendre(int n_points);

/// The degree hencky uses for this cell's stiffness and loads:
/// tet4 1 (1 point), tet10 2 (4 points), hex8 3 (2x2x2 Gauss), hex20 5 (3x3x3), wedge6 2 (3-point
/// triangle x 2-point Gauss = 6 points), tri3 2 (3 points), tri6 4 (6 points), quad4 3 (2x2),
/// quad8 5 (3x3).
int default_degree(CellType type);

}  // namespace hencky
