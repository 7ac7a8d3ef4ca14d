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
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <climits>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "core/packed_bytes.hpp"
#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"
#include "solve/model.hpp"
#include "solve/rigid_motions.hpp"

namespace hencky {
namespace {

/// Disjoint sets of 0 .. n-1 (union-find with path halving): a set is named by its root.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int root(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  /// The set of a and b, named by the smaller root (the first member in order stays its name).
  void join(int a, int b) {
    a = root(a), b = root(b);
    parent[std::max(a, b)] = std::min(a, b);
  }
};

/// The connected bodies of the mesh's cells: a body index per node (-1: a node of no cell).
struct Bodies {
  std::vector<int> of_node;
  int count = 0;
};

Bodies connected_bodies(const Mesh& mesh) {
  DisjointSets sets(mesh.n_nodes());
  std::vector<char> used(mesh.n_nodes(), 0);
  for (int e = 0; e < mesh.cells.size(); ++e) {
    const auto nodes = mesh.cells.nodes(e);
    for (int n : nodes) used[n] = 1;
    for (std::size_t a = 1; a < nodes.size(); ++a) sets.join(nodes[a], nodes[0]);
  }
  Bodies b;
  b.of_node.assign(mesh.n_nodes(), -1);
  std::vector<int> index(mesh.n_nodes(), -1);
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    if (!used[n]) continue;
    int& k = index[sets.root(n)];
    if (k < 0) k = b.count++;
    b.of_node[n] = k;
  }
  return b;
}

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

/// One connected piece of a rank's cells, or a body (bodies_of: the pieces that share a node),
/// in sums that add up across the ranks: its own nodes' count and coordinates, its bounding box,
/// its first cell in the whole mesh's order (which names it), and the rows of its prescribed
/// dofs and contact normals, Σ rowᵀrow, about its centre `ref` with rotations scaled by its
/// size `scale` (a body's: the mean of its nodes and the diagonal of its bounding box).
struct Piece {
  Vec3 ref = Vec3::Zero();
  double scale = 1, nodes = 0;
  Vec3 sum = Vec3::Zero(), lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  long long first_cell = LLONG_MAX, cells = 0;
  long first_tag = 0;  ///< the first cell's element tag
  int region = -1;     ///< and its region
  Mat6d held = Mat6d::Zero(), contact = Mat6d::Zero();
  std::vector<long long> shared;  ///< the whole mesh's numbers of its nodes other ranks hold
};

/// A 6×6 matrix as its 36 values (Eigen's matrices are not trivially copyable types).
using Mat6Values = std::array<double, 36>;

void put_piece(ByteWriter& w, const Piece& p) {
  for (const Vec3* v : {&p.ref, &p.sum, &p.lo, &p.hi}) w.value(std::array{v->x(), v->y(), v->z()});
  w.value(p.scale);
  w.value(p.nodes);
  w.value(p.first_cell);
  w.value(p.cells);
  w.value(p.first_tag);
  w.value(p.region);
  for (const Mat6d* m : {&p.held, &p.contact}) {
    Mat6Values a;
    std::copy(m->data(), m->data() + a.size(), a.begin());
    w.value(a);
  }
  w.vector(p.shared);
}

Piece get_piece(ByteReader& r) {
  Piece p;
  for (Vec3* v : {&p.ref, &p.sum, &p.lo, &p.hi}) {
    std::array<double, 3> x{};
    r.value(x);
    *v = Vec3(x[0], x[1], x[2]);
  }
  r.value(p.scale);
  r.value(p.nodes);
  r.value(p.first_cell);
  r.value(p.cells);
  r.value(p.first_tag);
  r.value(p.region);
  for (Mat6d* m : {&p.held, &p.contact}) {
    Mat6Values a{};
    r.value(a);
    std::copy(a.begin(), a.end(), m->data());
  }
  r.vector(p.shared);
  return p;
}

/// The bodies the pieces make: pieces that share a node are one body, its sums moved to its
/// own centre and size. In the order of each body's first piece.
std::vector<Piece> bodies_of(const std::vector<Piece>& pieces) {
  DisjointSets sets(pieces.size());
  std::unordered_map<long long, int> holder;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i)
    for (long long g : pieces[i].shared)
      if (auto [it, fresh] = holder.emplace(g, i); !fresh) sets.join(it->second, i);
  std::vector<int> index(pieces.size(), -1);
  std::vector<std::vector<int>> of_body;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i) {
    int& k = index[sets.root(i)];
    if (k < 0) {
      k = static_cast<int>(of_body.size());
      of_body.emplace_back();
    }
    of_body[k].push_back(i);
  }
  std::vector<Piece> bodies;
  for (const std::vector<int>& members : of_body) {
    Piece b;
    for (int i : members) {
      const Piece& p = pieces[i];
      b.nodes += p.nodes;
      b.sum += p.sum;
      b.lo = b.lo.cwiseMin(p.lo);
      b.hi = b.hi.cwiseMax(p.hi);
      b.cells += p.cells;
      if (p.first_cell < b.first_cell)
        std::tie(b.first_cell, b.first_tag, b.region) = std::tie(p.first_cell, p.first_tag, p.region);
    }
    b.ref = b.nodes > 0 ? Vec3(b.sum / b.nodes) : pieces[members[0]].ref;
    b.scale = std::max((b.hi - b.lo).norm(), 1e-300);
    for (int i : members) {
      const Piece& p = pieces[i];
      b.held += moved(p.held, p.ref, p.scale, b.ref, b.scale);
      b.contact += moved(p.contact, p.ref, p.scale, b.ref, b.scale);
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
    ByteWriter mine;
    for (const Piece& p : pieces) put_piece(mine, p);
    std::string all;
    for (const std::string& bytes : par::gather_strings(mine.bytes())) all += bytes;
    par::broadcast(all);
    pieces.clear();
    for (ByteReader r(all, "check_held: the ranks' pieces are cut short"); !r.done();)
      pieces.push_back(get_piece(r));
  }
  const std::vector<Piece> bodies = bodies_of(pieces);
  for (const Piece& b : bodies) {
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
          name, fmt::join(describe_motions(free, b.ref, b.scale), "; ")));
      continue;
    }
    throw InputError(
        SourceLocation{case_->file.string(), 0, 0, "boundary"},
        fmt::format("{} is not held: its displacement conditions{} leave {} rigid motion{} "
                    "free: {}. Prescribe displacements that stop {}: a translation needs its "
                    "component prescribed somewhere, a rotation a component across its axis at a "
                    "node away from it",
                    name, contacts_.empty() ? "" : " and its contacts", unheld.cols(),
                    unheld.cols() > 1 ? "s" : "", fmt::join(describe_motions(unheld, b.ref, b.scale), "; "),
                    unheld.cols() > 1 ? "them" : "it"));
  }
}

}  // namespace hencky
