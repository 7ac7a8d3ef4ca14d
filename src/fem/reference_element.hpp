#pragma once
// Reference (parent) elements: nodes, shape functions and their natural-coordinate gradients, in
// Gmsh's node ordering and on Gmsh's reference domains (see fem/quadrature.hpp for the domains).
//
//   tet4    N_a = L_a with L = (1 - xi - eta - zeta, xi, eta, zeta)
//   tet10   corners L_a (2 L_a - 1); edge nodes 4..9 on edges (0,1) (1,2) (2,0) (3,0) (3,2) (3,1):
//           4 L_i L_j
//   hex8    trilinear, nodes (-1,-1,-1) (1,-1,-1) (1,1,-1) (-1,1,-1), then the same at zeta = +1
//   hex20   serendipity; edge nodes 8..19 on edges (0,1) (0,3) (0,4) (1,2) (1,5) (2,3) (2,6) (3,7)
//           (4,5) (4,7) (5,6) (6,7)
//   wedge6  (1 - xi - eta, xi, eta) x ((1 - zeta)/2, (1 + zeta)/2); nodes 0,1,2 at zeta = -1
//   tri3    (1 - xi - eta, xi, eta)
//   tri6    corners L_a (2 L_a - 1); edge nodes 3,4,5 on edges (0,1) (1,2) (2,0): 4 L_i L_j
//   quad4   bilinear, nodes (-1,-1) (1,-1) (1,1) (-1,1)
//   quad8   serendipity; edge nodes 4..7 on edges (0,1) (1,2) (2,3) (3,0)
#include <Eigen/Dense>
#include <array>
#include <vector>

#include "fem/cell_type.hpp"

namespace hencky {

/// Natural coordinates of node a at [3*a + k] (k < 3; unused trailing coordinates are 0).
const double* node_coordinates(CellType type);

/// Shape function values at the natural coordinates xi[0..dim): N[a], a < cell_n_nodes(type).
/// No allocation; xi and N may not overlap.
void shape_values(CellType type, const double* xi, double* N);

/// Natural gradients at xi: dN[a*dim + k] = dN_a/dxi_k, dim = cell_dim(type). No allocation.
void shape_gradients(CellType type, const double* xi, double* dN);

/// Everything an element kernel needs for one cell type and quadrature rule.
struct ReferenceTable {
  CellType type = CellType::tet4;
  int degree = 0;               ///< degree of the quadrature rule used (>= the degree asked for)
  int dim = 0;                  ///< cell_dim(type)
  int n_nodes = 0;              ///< cell_n_nodes(type)
  int n_points = 0;             ///< integration points
  std::vector<double> weights;  ///< [q]
  std::vector<std::array<double, 3>> points;  ///< [q], natural coordinates
  std::vector<double> N;                      ///< [q*n_nodes + a]
  std::vector<double> dN;                     ///< [(q*n_nodes + a)*dim + k] = dN_a/dxi_k at point q
  /// n_nodes x n_points: nodal values = extrapolation * (integration-point values). Least-squares
  /// fit of the point values in the span of the shape functions of cell_linear(type) (corner
  /// nodes only), evaluated at every node (mid-edge nodes get the linear field there). With fewer
  /// points than corners (one-point rules) it is the mean of the point values at every node.
  Eigen::MatrixXd extrapolation;
  /// [q*n_nodes + a]: a point's temperature from the nodes' as ccx takes it in a quadratic cell
  /// (temperature.interpolation: linear). hex20: the cell's interpolation projected onto the
  /// trilinear functions (least squares over the points with their weights), ccx's C3D20
  /// (its lintemp.f holds this table, to 9 digits, for the 27 points); other quadratic cells: the
  /// corners' values with the linear cell's functions (ccx's C3D10T). Empty for linear cells.
  std::vector<double> N_linear_temperature;
};

/// The table for (type, quadrature(type, degree)). Built on first use and cached for the life of
/// the program; safe to call concurrently (e.g. from OpenMP threads); the reference stays valid.
/// Throws std::invalid_argument like quadrature() when no rule of that degree exists.
const ReferenceTable& reference_table(CellType type, int degree);

/// reference_table(type, default_degree(type)).
const ReferenceTable& reference_table(CellType type);

}  // namespace hencky
