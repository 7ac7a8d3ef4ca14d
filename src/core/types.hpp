#pragma once
// Small fixed-size math used everywhere. Voigt order is the formulation's (1.10):
// {11, 22, 33, 23, 31, 12}, strains with engineering shears (2*eps_23, ...).
#include <Eigen/Dense>
#include <cstdint>

namespace hencky {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Voigt = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Largest number of nodes of any supported cell (20-node hexahedron).
inline constexpr int max_cell_nodes = 20;
/// Largest number of integration points of any volume rule in use (3x3x3 Gauss).
inline constexpr int max_cell_points = 27;

}  // namespace hencky
