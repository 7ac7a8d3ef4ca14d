// Model::check_held (model.hpp): every body is held against its six rigid motions before
// anything is solved. The test is exact and does not depend on a factorization's pivots or
// ordering: a rigid motion u(x) = t + ω × (x − c) of a connected body leaves every prescribed
// degree of freedom at zero only if it lies in the null space of the 6-column matrix whose
// rows are the prescribed dofs' components of the six unit motions. Where the displacement
// conditions leave a motion free, rows for the contact nodes along their surface's normal say
// whether contact may stop it (a block pressed by a rigid tool): then a warning, else an input
// error naming the body, the motion and what would hold it.
#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>

#include "solve/model.hpp"

namespace hencky {
namespace {

using Mat6d = Eigen::Matrix<double, 6, 6>;
using Vec6d = Eigen::Matrix<double, 6, 1>;

/// The connected bodies of the mesh's cells: a body index per node (-1: a node of no cell).
struct Bodies {
  std::vector<int> of_node;
  int count = 0;
};

Bodies connected_bodies(const Mesh& mesh) {
  std::vector<int> parent(mesh.n_nodes());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int n) {
    while (parent[n] != n) n = parent[n] = parent[parent[n]];
    return n;
  };
  std::vector<char> used(mesh.n_nodes(), 0);
  for (int e = 0; e < mesh.cells.size(); ++e) {
    const auto nodes = mesh.cells.nodes(e);
    for (int n : nodes) used[n] = 1;
    for (std::size_t a = 1; a < nodes.size(); ++a) parent[root(nodes[a])] = root(nodes[0]);
  }
  Bodies b;
  b.of_node.assign(mesh.n_nodes(), -1);
  std::vector<int> index(mesh.n_nodes(), -1);
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    if (!used[n]) continue;
    int& k = index[root(n)];
    if (k < 0) k = b.count++;
    b.of_node[n] = k;
  }
  return b;
}

/// One body: where it is, and the rows of its prescribed dofs and contact normals.
struct Body {
  Vec3 centre = Vec3::Zero();
  double size = 0;  ///< the diagonal of its bounding box
  int nodes = 0, first_cell = -1, cells = 0;
  Mat6d held = Mat6d::Zero();     ///< Σ rowᵀrow over the prescribed dofs
  Mat6d contact = Mat6d::Zero();  ///< the same over the contact nodes' normals
};

/// The row of the six unit motions' components along `d` at x: translations along x, y, z and
/// rotations about the body's centre, e_j × (x − c)/L, scaled by its size to be of one order.
Vec6d motion_row(const Body& b, const Vec3& x, const Vec3& d) {
  const Vec3 r = (x - b.centre) / b.size;
  Vec6d row;
  for (int j = 0; j < 3; ++j) {
    row[j] = d[j];
    row[3 + j] = Vec3::Unit(j).cross(r).dot(d);
  }
  return row;
}

/// The spectral parts of a 6×6 positive semidefinite matrix: its null space and the range with
/// its eigenvalues. An eigenvalue up to 1e-10 of the largest (or of 1) counts as zero. One
/// 6×6 symmetric eigensolver does all the linear algebra of this file: it is exact enough for
/// these small, well-scaled matrices, and one template instance keeps the file quick to build.
struct Spectrum {
  Eigen::SelfAdjointEigenSolver<Mat6d> eig;
  std::vector<int> zero, positive;
  explicit Spectrum(const Mat6d& a) : eig(a) {
    const double top = std::max(eig.eigenvalues().maxCoeff(), 1.0);
    for (int i = 0; i < 6; ++i)
      (eig.eigenvalues()[i] > 1e-10 * top ? positive : zero).push_back(i);
  }
  Eigen::MatrixXd columns(const std::vector<int>& which) const {
    Eigen::MatrixXd c(6, which.size());
    for (std::size_t k = 0; k < which.size(); ++k) c.col(k) = eig.eigenvectors().col(which[k]);
    return c;
  }
  /// The Moore–Penrose inverse.
  Mat6d pseudo_inverse() const {
    Mat6d p = Mat6d::Zero();
    for (int i : positive) {
      const Vec6d v = eig.eigenvectors().col(i);
      p += v * v.transpose() / eig.eigenvalues()[i];
    }
    return p;
  }
};

/// The motions a 6×6 positive semidefinite matrix leaves free (its null space, orthonormal).
Eigen::MatrixXd free_motions(const Mat6d& a) {
  const Spectrum s(a);
  return s.columns(s.zero);
}

std::string point_text(const Vec3& p, double size) {
  auto c = [&](double v) { return std::abs(v) < 1e-9 * size ? 0.0 : v; };
  return fmt::format("({:.4g}, {:.4g}, {:.4g})", c(p.x()), c(p.y()), c(p.z()));
}

/// The free motions of null space `n` in words: the translations along x, y, z and the
/// rotations about axes along x, y, z it contains, then any other motion it holds.
std::vector<std::string> describe(const Eigen::MatrixXd& n, const Body& b) {
  static const char* axis[3] = {"x", "y", "z"};
  const Mat6d q = Mat6d::Identity() - n * n.transpose();  // the held part of a motion
  std::vector<std::string> out;
  Eigen::MatrixXd found(6, 0);
  auto keep = [&](const Vec6d& v) {
    found.conservativeResize(6, found.cols() + 1);
    found.col(found.cols() - 1) = v.normalized();
  };
  for (int i = 0; i < 3; ++i) {
    const Vec6d t = Vec6d::Unit(i);
    if ((q * t).norm() < 1e-6) {
      out.push_back(fmt::format("translation along {}", axis[i]));
      keep(t);
    }
  }
  for (int j = 0; j < 3; ++j) {
    // The rotation about some axis along e_j: [t; e_j] with the t that holds it least.
    // t = −(q's translation columns)⁺ q e_j, the least-squares t of least norm.
    Mat6d qt = Mat6d::Zero();
    qt.leftCols<3>() = q.leftCols<3>();
    const Vec6d rot = Vec6d::Unit(3 + j);
    const Vec6d t6 = -Spectrum(qt.transpose() * qt).pseudo_inverse() * qt.transpose() * (q * rot);
    const Vec3 t = t6.head<3>();
    Vec6d v = rot;
    v.head<3>() = t;
    if ((q * v).norm() > 1e-6 * v.norm()) continue;
    const Vec3 e = Vec3::Unit(j);
    const Vec3 across = t - t.dot(e) * e;  // the part of t along e is a translation
    const Vec3 p = b.centre + b.size * e.cross(across);
    out.push_back(
        fmt::format("rotation about the axis through {} along {}", point_text(p, b.size), axis[j]));
    v.head<3>() = across;
    keep(v);
  }
  // What the coordinate motions do not span: described by their vectors.
  if (found.cols() < n.cols()) {
    // The part of n outside the span of what was found, and an orthonormal basis of it (the
    // range of rest restᵀ: the left singular vectors of rest above 1e-5).
    const Spectrum spanned(found * found.transpose());
    const Eigen::MatrixXd in_span = spanned.columns(spanned.positive);
    const Eigen::MatrixXd rest = n - in_span * (in_span.transpose() * n);
    const Spectrum left(rest * rest.transpose());
    for (int k : left.positive) {
      const Vec6d v = left.eig.eigenvectors().col(k);
      const Vec3 w(v[3], v[4], v[5]);
      if (w.norm() < 1e-9) {
        out.push_back("translation along " + point_text(Vec3(v[0], v[1], v[2]).normalized(), 1));
        continue;
      }
      const Vec3 e = w.normalized(), t(v[0], v[1], v[2]);
      const Vec3 across = (t - t.dot(e) * e) / w.norm();
      out.push_back(fmt::format("rotation about the axis through {} along {}",
                                point_text(b.centre + b.size * e.cross(across), b.size),
                                point_text(e, 1)));
    }
  }
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "; " : "") + v[i];
  return s;
}

}  // namespace

void Model::check_held(Log& log) const {
  const Bodies parts = connected_bodies(mesh_);
  std::vector<Body> bodies(parts.count);
  std::vector<Vec3> lo(parts.count, Vec3::Constant(INFINITY)), hi(parts.count, -lo[0]);
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    const int k = parts.of_node[n];
    if (k < 0) continue;
    bodies[k].centre += mesh_.x[n];
    ++bodies[k].nodes;
    lo[k] = lo[k].cwiseMin(mesh_.x[n]);
    hi[k] = hi[k].cwiseMax(mesh_.x[n]);
  }
  for (int k = 0; k < parts.count; ++k) {
    bodies[k].centre /= bodies[k].nodes;
    bodies[k].size = std::max((hi[k] - lo[k]).norm(), 1e-300);
  }
  for (int e = 0; e < mesh_.cells.size(); ++e) {
    Body& b = bodies[parts.of_node[mesh_.cells.nodes(e)[0]]];
    if (b.first_cell < 0) b.first_cell = e;
    ++b.cells;
  }
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    const int k = parts.of_node[n];
    if (k < 0) continue;
    for (int d = 0; d < 3; ++d) {
      if (dofs_.eq[3 * static_cast<std::size_t>(n) + d] >= 0) continue;
      const Vec6d row = motion_row(bodies[k], mesh_.x[n], Vec3::Unit(d));
      bodies[k].held += row * row.transpose();
    }
  }
  for (const ContactBody& cb : contacts_)
    for (const ContactPoint& p : cb.points) {
      const int k = parts.of_node[p.node];
      if (k < 0) continue;
      const Vec6d row = motion_row(bodies[k], p.x, cb.surface->nearest(p.x).n);
      bodies[k].contact += row * row.transpose();
    }
  for (int k = 0; k < parts.count; ++k) {
    const Body& b = bodies[k];
    const Eigen::MatrixXd free = free_motions(b.held);
    if (free.cols() == 0) continue;
    const int region = mesh_.cell_region[b.first_cell];
    const std::string name =
        parts.count == 1 ? "the body"
                         : fmt::format("the body of element {}{} ({} elements)",
                                       mesh_.cells.tag[b.first_cell],
                                       region >= 0 ? " in region '" + mesh_.regions[region].name + "'"
                                                   : std::string(),
                                       b.cells);
    const Eigen::MatrixXd unheld = free_motions(b.held + b.contact);
    if (unheld.cols() == 0) {
      log.warn(fmt::format(
          "{} is held by contact alone against {}: the displacement conditions leave it free, "
          "and only the rigid surfaces can stop it (a step where they do not touch it fails)",
          name, joined(describe(free, b))));
      continue;
    }
    throw InputError(
        SourceLocation{case_->file.string(), 0, 0, "boundary"},
        fmt::format("{} is not held: its displacement conditions{} leave {} rigid motion{} "
                    "free: {}. Prescribe displacements that stop {}: a translation needs its "
                    "component prescribed somewhere, a rotation a component across its axis at a "
                    "node away from it",
                    name, contacts_.empty() ? "" : " and its contacts", unheld.cols(),
                    unheld.cols() > 1 ? "s" : "", joined(describe(unheld, b)),
                    unheld.cols() > 1 ? "them" : "it"));
  }
}

}  // namespace hencky
