// Model::check_held (model.hpp): every body is held against its six rigid motions before
// anything is solved. The test is exact and does not depend on a factorization's pivots or
// ordering: a rigid motion u(x) = t + ω × (x − c) of a connected body leaves every prescribed
// degree of freedom at zero only if it lies in the null space of the 6-column matrix whose
// rows are the prescribed dofs' components of the six unit motions. Where the displacement
// conditions leave a motion free, rows for the contact nodes along their surface's normal say
// whether contact may stop it (a block pressed by a rigid tool): then a warning, else an input
// error naming the body, the motion and what would hold it. On a mesh split over the ranks each
// rank sums the rows of its connected pieces about their own centres; the pieces that share a
// node are one body, whose sums are moved to its centre (exact: the rows are linear in it).
#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <numeric>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"
#include "solve/model.hpp"
#include "solve/rigid_motions.hpp"

namespace hencky {
namespace {


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

/// One body: where it is, the cell that names it, and the rows of its prescribed dofs and
/// contact normals about its centre, rotations scaled by its size.
struct Body {
  Vec3 centre = Vec3::Zero();
  double size = 0;  ///< the diagonal of its bounding box
  long long first_cell = LLONG_MAX, cells = 0;  ///< the first cell in the whole mesh's order
  long first_tag = 0;                           ///< its element tag
  int region = -1;                              ///< and its region
  Mat6d held = Mat6d::Zero();     ///< Σ rowᵀrow over the prescribed dofs
  Mat6d contact = Mat6d::Zero();  ///< the same over the contact nodes' normals
};

/// The row of the six unit motions' components along `d` at x: translations along x, y, z and
/// rotations about `ref`, e_j × (x − ref)/scale, scaled to be of one order.
Vec6d motion_row(const Vec3& ref, double scale, const Vec3& x, const Vec3& d) {
  const Vec3 r = (x - ref) / scale;
  Vec6d row;
  for (int j = 0; j < 3; ++j) {
    row[j] = d[j];
    row[3 + j] = Vec3::Unit(j).cross(r).dot(d);
  }
  return row;
}

/// Σ rowᵀrow of rows about (ref1, scale1) made the sum of the same rows about (ref2, scale2):
/// the rotation parts are (scale1 ρ1_j + (e_j × (ref1 − ref2))·d)/scale2, linear in the row.
Mat6d moved(const Mat6d& m, const Vec3& ref1, double scale1, const Vec3& ref2, double scale2) {
  Mat6d t = Mat6d::Identity();
  for (int j = 0; j < 3; ++j) {
    const Vec3 k = Vec3::Unit(j).cross(ref1 - ref2) / scale2;
    for (int i = 0; i < 3; ++i) t(3 + j, i) = k[i];
    t(3 + j, 3 + j) = scale1 / scale2;
  }
  return t * m * t.transpose();
}

/// One connected piece of a rank's cells (the whole body on a whole mesh), in sums that add up
/// across the ranks whose pieces make one body: its own nodes' count and coordinates, its
/// bounding box, its first cell, and its rows about its own centre and size (ref, scale).
struct Piece {
  Vec3 ref = Vec3::Zero();
  double scale = 1, nodes = 0;
  Vec3 sum = Vec3::Zero(), lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  long long first_cell = LLONG_MAX, cells = 0;
  long first_tag = 0;
  int region = -1;
  Mat6d held = Mat6d::Zero(), contact = Mat6d::Zero();
  std::vector<long long> shared;  ///< the whole mesh's numbers of its nodes other ranks hold
};

std::string to_text(const Piece& p) {
  std::string s = fmt::format("{:.17g} {:.17g} {:.17g} {:.17g} {:.17g}", p.ref.x(), p.ref.y(),
                              p.ref.z(), p.scale, p.nodes);
  for (const Vec3* v : {&p.sum, &p.lo, &p.hi})
    s += fmt::format(" {:.17g} {:.17g} {:.17g}", v->x(), v->y(), v->z());
  s += fmt::format(" {} {} {} {}", p.first_cell, p.cells, p.first_tag, p.region);
  for (const Mat6d* m : {&p.held, &p.contact})
    for (int i = 0; i < 36; ++i) s += fmt::format(" {:.17g}", (*m)(i));
  s += fmt::format(" {}", p.shared.size());
  for (long long g : p.shared) s += fmt::format(" {}", g);
  return s + "\n";
}

Piece from_text(std::istream& in) {
  Piece p;
  std::size_t n = 0;
  in >> p.ref.x() >> p.ref.y() >> p.ref.z() >> p.scale >> p.nodes;  // as to_text wrote them
  for (Vec3* v : {&p.sum, &p.lo, &p.hi}) in >> v->x() >> v->y() >> v->z();
  in >> p.first_cell >> p.cells >> p.first_tag >> p.region;
  for (Mat6d* m : {&p.held, &p.contact})
    for (int i = 0; i < 36; ++i) in >> (*m)(i);
  in >> n;
  p.shared.resize(n);
  for (long long& g : p.shared) in >> g;
  return p;
}

/// The bodies the pieces make: pieces that share a node are one body. In the order of each
/// body's first piece.
std::vector<Body> bodies_of(const std::vector<Piece>& pieces) {
  std::vector<int> parent(pieces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::unordered_map<long long, int> holder;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i)
    for (long long g : pieces[i].shared)
      if (auto [it, fresh] = holder.emplace(g, i); !fresh) {
        const int a = root(it->second), b = root(i);
        parent[std::max(a, b)] = std::min(a, b);
      }
  std::vector<int> index(pieces.size(), -1);
  std::vector<std::vector<int>> of_body;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i) {
    int& k = index[root(i)];
    if (k < 0) {
      k = static_cast<int>(of_body.size());
      of_body.emplace_back();
    }
    of_body[k].push_back(i);
  }
  std::vector<Body> bodies;
  for (const std::vector<int>& members : of_body) {
    Body b;
    double nodes = 0;
    Vec3 sum = Vec3::Zero(), lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (int i : members) {
      const Piece& p = pieces[i];
      nodes += p.nodes;
      sum += p.sum;
      lo = lo.cwiseMin(p.lo);
      hi = hi.cwiseMax(p.hi);
      b.cells += p.cells;
      if (p.first_cell < b.first_cell)
        std::tie(b.first_cell, b.first_tag, b.region) = std::tie(p.first_cell, p.first_tag, p.region);
    }
    b.centre = nodes > 0 ? Vec3(sum / nodes) : pieces[members[0]].ref;
    b.size = std::max((hi - lo).norm(), 1e-300);
    for (int i : members) {
      const Piece& p = pieces[i];
      b.held += moved(p.held, p.ref, p.scale, b.centre, b.size);
      b.contact += moved(p.contact, p.ref, p.scale, b.centre, b.size);
    }
    bodies.push_back(b);
  }
  return bodies;
}

/// This rank's pieces: the connected parts of its cells. On a part (`part`), the node counts and
/// rows are its own nodes' (each node counted once over the ranks) and `shared` lists the
/// nodes with copies on other ranks (`copies`: each node's count of copies).
std::vector<Piece> pieces_of(const Mesh& mesh, const DofMap& dofs,
                             const std::vector<ContactBody>& contacts, const MeshPart* part,
                             const std::vector<double>& copies) {
  const Bodies parts = connected_bodies(mesh);
  std::vector<Piece> pieces(parts.count);
  std::vector<double> count(parts.count, 0.0);
  const int owned = part ? part->owned_nodes : mesh.n_nodes();
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    const int k = parts.of_node[n];
    if (k < 0) continue;
    Piece& p = pieces[k];
    p.ref += mesh.x[n];
    count[k] += 1;
    p.lo = p.lo.cwiseMin(mesh.x[n]);
    p.hi = p.hi.cwiseMax(mesh.x[n]);
    if (n < owned) {
      p.nodes += 1;
      p.sum += mesh.x[n];
    }
    if (part && copies[n] > 1.5) p.shared.push_back(part->global_node[n]);
  }
  for (int k = 0; k < parts.count; ++k) {
    pieces[k].ref /= count[k];
    pieces[k].scale = std::max((pieces[k].hi - pieces[k].lo).norm(), 1e-300);
  }
  for (int e = 0; e < mesh.cells.size(); ++e) {
    Piece& p = pieces[parts.of_node[mesh.cells.nodes(e)[0]]];
    const long long whole = part ? part->global_cell[e] : e;
    if (whole < p.first_cell) {
      p.first_cell = whole;
      p.first_tag = mesh.cells.tag[e];
      p.region = mesh.cell_region[e];
    }
    ++p.cells;
  }
  for (int n = 0; n < owned; ++n) {
    const int k = parts.of_node[n];
    if (k < 0) continue;
    for (int d = 0; d < 3; ++d) {
      if (dofs.eq[3 * static_cast<std::size_t>(n) + d] >= 0) continue;
      const Vec6d row = motion_row(pieces[k].ref, pieces[k].scale, mesh.x[n], Vec3::Unit(d));
      pieces[k].held += row * row.transpose();
    }
  }
  for (const ContactBody& cb : contacts)
    for (const ContactPoint& cp : cb.points) {
      const int k = parts.of_node[cp.node];
      if (k < 0 || cp.node >= owned) continue;
      const Vec6d row = motion_row(pieces[k].ref, pieces[k].scale, cp.x, cb.surface->nearest(cp.x).n);
      pieces[k].contact += row * row.transpose();
    }
  return pieces;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "; " : "") + v[i];
  return s;
}

}  // namespace

void Model::check_held(Log& log) const {
  const MeshPart* part = dist_.part ? &*dist_.part : nullptr;
  std::vector<double> copies;
  if (part) {
    copies.assign(mesh_.n_nodes(), 1.0);
    dist_.exchange->sum(copies, 1);
  }
  std::vector<Piece> pieces = pieces_of(mesh_, dofs_, contacts_, part, copies);
  if (part) {
    // Every rank gets every rank's pieces and finds the same bodies and the same verdict.
    std::string all;
    std::string mine;
    for (const Piece& p : pieces) mine += to_text(p);
    for (const std::string& text : par::gather_strings(mine)) all += text;
    par::broadcast(all);
    pieces.clear();
    std::istringstream in(all);
    for (in >> std::ws; !in.eof(); in >> std::ws) pieces.push_back(from_text(in));
  }
  const std::vector<Body> bodies = bodies_of(pieces);
  for (const Body& b : bodies) {
    const Eigen::MatrixXd free = free_motions(b.held);
    if (free.cols() == 0) continue;
    const std::string name =
        bodies.size() == 1
            ? "the body"
            : fmt::format("the body of element {}{} ({} elements)", b.first_tag,
                          b.region >= 0 ? " in region '" + mesh_.regions[b.region].name + "'"
                                        : std::string(),
                          b.cells);
    const Eigen::MatrixXd unheld = free_motions(b.held + b.contact);
    if (unheld.cols() == 0) {
      log.warn(fmt::format(
          "{} is held by contact alone against {}: the displacement conditions leave it free, "
          "and only the rigid surfaces can stop it (a step where they do not touch it fails)",
          name, joined(describe_motions(free, b.centre, b.size))));
      continue;
    }
    throw InputError(
        SourceLocation{case_->file.string(), 0, 0, "boundary"},
        fmt::format("{} is not held: its displacement conditions{} leave {} rigid motion{} "
                    "free: {}. Prescribe displacements that stop {}: a translation needs its "
                    "component prescribed somewhere, a rotation a component across its axis at a "
                    "node away from it",
                    name, contacts_.empty() ? "" : " and its contacts", unheld.cols(),
                    unheld.cols() > 1 ? "s" : "", joined(describe_motions(unheld, b.centre, b.size)),
                    unheld.cols() > 1 ? "them" : "it"));
  }
}

}  // namespace hencky
