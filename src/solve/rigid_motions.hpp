#pragma once
// The rigid motions a body's supports leave free (Model::check_held, model_held.cpp): the null
// space of a 6×6 positive semidefinite matrix of the six unit motions (translations along x, y,
// z, then rotations about the body's centre scaled by its size), and those motions in words.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace hencky {

using Mat6d = Eigen::Matrix<double, 6, 6>;
using Vec6d = Eigen::Matrix<double, 6, 1>;

/// The motions the matrix leaves free (its null space, orthonormal columns).
Eigen::MatrixXd free_motions(const Mat6d& a);

/// The free motions of null space `n` of a body about `centre` of size `size`: the translations
/// along x, y, z and the rotations about axes along x, y, z it contains ("rotation about the axis
/// through (0.05, 0, 0) along x"), then any other motion it holds, by its vectors.
std::vector<std::string> describe_motions(const Eigen::MatrixXd& n, const Vec3& centre,
                                          double size);

}  // namespace hencky
