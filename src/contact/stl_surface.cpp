#include "contact/stl_surface.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <string_view>
#include <unordered_map>

#include "contact/stl_file.hpp"
#include "contact/surface_type.hpp"
#include "core/error.hpp"

namespace hencky {
namespace {

namespace fs = std::filesystem;
using stl::check_scale;
using stl::parse_stl;
using stl::point_str;
using stl::read_stl_file;
using stl::Soup;

constexpr double inf = std::numeric_limits<double>::infinity();
// Tolerances, relative to the bounding-box diagonal unless dimensionless. Coordinates carry
// ~1e-16 relative error, the queries' arithmetic a few hundred times that.
constexpr double round_off = 1e-12;        // a point this close to a plane is on it
constexpr double direction_floor = 1e-9;   // below it, p - x has too few digits to be a normal
constexpr double barycentric_tol = 1e-10;  // a hit on a shared edge is in both triangles
constexpr double parallel_tol = 1e-12;     // |sin| of a segment's angle to a face it slides on
constexpr double sliver_tol = 1e-12;       // |e1 x e2| / (longest edge)^2 of a zero-area triangle
constexpr int leaf_size = 4;
// Faces meeting at a dihedral angle below this (their normals within it) are facets of one
// smooth surface, whose contact normal is interpolated across them; at a larger angle the
// edge is a crease of the body (a punch's rim) and keeps its sharp normals.
const double crease_cos = std::cos(30.0 * std::numbers::pi / 180);

struct CoordHash {
  std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::uint64_t v : k) h = (h ^ v) * 0xff51afd7ed558ccdull, h ^= h >> 33;
    return static_cast<std::size_t>(h);
  }
};

/// Closest point of triangle (a, b, c) to p and the feature it lies on, by the Voronoi regions
/// of the corners, then the edges, then the face: the region method of C. Ericson,
/// "Real-Time Collision Detection", Morgan Kaufmann 2005, sec. 5.1.5. The d's are projections
/// of p - corner on the edges ab and ac; the w's are the unnormalised barycentric weights.
struct TrianglePoint {
  Vec3 x;
  int feature;  // 0 face, 1 + k edge k (corner k to k + 1), 4 + k corner k
};
TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, 4};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, 5};
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, 6};
  const double wc = d1 * d4 - d3 * d2;
  if (wc <= 0 && d1 >= 0 && d3 <= 0) return {a + (d1 / (d1 - d3)) * ab, 1};
  const double wb = d5 * d2 - d1 * d6;
  if (wb <= 0 && d2 >= 0 && d6 <= 0) return {a + (d2 / (d2 - d6)) * ac, 3};
  const double wa = d3 * d6 - d5 * d4;
  if (wa <= 0 && d4 >= d3 && d5 >= d6) {
    const double u = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + u * (c - b), 2};
  }
  const double s = 1 / (wa + wb + wc);
  return {a + (wb * s) * ab + (wc * s) * ac, 0};
}

/// Squared distance from p to a box (0 inside).
double box_distance2(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

/// Slab test: the parameter at which a + s d enters the box padded by `pad`, for s in
/// [0, s_max], or inf when it misses.
double segment_box_entry(const Vec3& lo, const Vec3& hi, double pad, const Vec3& a, const Vec3& d,
                         double s_max) {
  double s0 = 0, s1 = s_max;
  for (int j = 0; j < 3; ++j) {
    const double l = lo[j] - pad, h = hi[j] + pad;
    if (d[j] == 0) {
      if (a[j] < l || a[j] > h) return inf;
      continue;
    }
    double t0 = (l - a[j]) / d[j], t1 = (h - a[j]) / d[j];
    if (t0 > t1) std::swap(t0, t1);
    s0 = std::max(s0, t0);
    s1 = std::min(s1, t1);
    if (s0 > s1) return inf;
  }
  return s0;
}

/// The corners welded into vertices: corners with exactly equal coordinates are one vertex
/// (+ 0.0 makes -0.0 and 0.0 one key), numbered in the order they are first met.
void weld(const Soup& soup, std::vector<Vec3>& x, std::vector<std::array<int, 3>>& tri) {
  std::unordered_map<std::array<std::uint64_t, 3>, int, CoordHash> index;
  index.reserve(soup.corners.size() / 2);
  tri.resize(soup.corners.size() / 3);
  for (std::size_t c = 0; c < soup.corners.size(); ++c) {
    const Vec3& xc = soup.corners[c];
    const std::array<std::uint64_t, 3> key{std::bit_cast<std::uint64_t>(xc[0] + 0.0),
                                           std::bit_cast<std::uint64_t>(xc[1] + 0.0),
                                           std::bit_cast<std::uint64_t>(xc[2] + 0.0)};
    const auto [it, inserted] = index.try_emplace(key, static_cast<int>(x.size()));
    if (inserted) x.push_back(xc);
    tri[c / 3][c % 3] = it->second;
  }
}

/// The unit normal of each triangle (counter-clockwise seen from outside). Throws InputError
/// at the triangle (`at_triangle(t)`) for one of zero area.
template <class At>
std::vector<Vec3> face_normals(const std::vector<Vec3>& x,
                               const std::vector<std::array<int, 3>>& tri, At&& at_triangle) {
  const int n_t = static_cast<int>(tri.size());
  std::vector<Vec3> face_n(n_t);
  for (int t = 0; t < n_t; ++t) {
    const Vec3 &a = x[tri[t][0]], &b = x[tri[t][1]], &c = x[tri[t][2]];
    const Vec3 n = (b - a).cross(c - a);
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (n.norm() <= sliver_tol * longest2)
      throw InputError(at_triangle(t),
                       fmt::format("triangle {} has zero area (vertices {}, {}, {}); remove it "
                                   "or repair the mesh",
                                   t + 1, point_str(a), point_str(b), point_str(c)));
    face_n[t] = n.normalized();
  }
  return face_n;
}

/// The volume the triangles enclose, by the divergence theorem, about a vertex to limit
/// cancellation (> 0 when the normals point out).
double enclosed_volume(const std::vector<Vec3>& x, const std::vector<std::array<int, 3>>& tri) {
  double volume = 0;
  const Vec3& o = x[0];
  for (const auto& t : tri) volume += (x[t[0]] - o).dot((x[t[1]] - o).cross(x[t[2]] - o)) / 6;
  return volume;
}

/// The angle of triangle t at its corner k.
double corner_angle(const std::vector<Vec3>& x, const std::array<int, 3>& t, int k) {
  const Vec3& xk = x[t[k]];
  const Vec3 u = x[t[(k + 1) % 3]] - xk, v = x[t[(k + 2) % 3]] - xk;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

/// Angle-weighted pseudo-normals (Bærentzen and Aanæs 2005): an edge's (edge k of triangle t
/// at 3t + k) is the sum of its two faces' normals (both weighted by pi), a vertex's the sum
/// of its faces' normals weighted by the angle of each face at the vertex.
void pseudo_normals(const std::vector<Vec3>& x, const std::vector<std::array<int, 3>>& tri,
                    const std::vector<Vec3>& face_n, const std::vector<int>& edge_nb,
                    std::vector<Vec3>& edge_n, std::vector<Vec3>& vertex_n) {
  const int n_t = static_cast<int>(tri.size());
  edge_n.resize(3 * n_t);
  vertex_n.assign(x.size(), Vec3::Zero());
  for (int t = 0; t < n_t; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 sum = face_n[t] + face_n[edge_nb[3 * t + k]];
      // Two faces back to back (a knife edge) have no pseudo-normal: take the face's own.
      edge_n[3 * t + k] = sum.norm() > 1e-8 ? sum.normalized() : face_n[t];
      vertex_n[tri[t][k]] += corner_angle(x, tri[t], k) * face_n[t];
    }
  }
  for (Vec3& n : vertex_n) n.normalize();
}

/// Smoothed normals (Phong-style): at each corner of a triangle (3t + k), the angle-weighted
/// mean of the normals of the faces at that vertex that lie on the same smooth part (within
/// the crease angle of the triangle's own); whether each edge (3t + k) and each vertex is free
/// of creases.
void smoothed_normals(const std::vector<Vec3>& x, const std::vector<std::array<int, 3>>& tri,
                      const std::vector<Vec3>& face_n, const std::vector<int>& edge_nb,
                      std::vector<Vec3>& corner_n, std::vector<std::uint8_t>& edge_smooth,
                      std::vector<std::uint8_t>& vertex_smooth) {
  const int n_t = static_cast<int>(tri.size());
  std::vector<int> vt_ptr(x.size() + 1, 0), vt_idx(3 * static_cast<std::size_t>(n_t));
  for (const auto& t : tri)
    for (int v : t) ++vt_ptr[v + 1];
  for (std::size_t v = 0; v < x.size(); ++v) vt_ptr[v + 1] += vt_ptr[v];
  {
    std::vector<int> fill(vt_ptr.begin(), vt_ptr.end() - 1);
    for (int t = 0; t < n_t; ++t)
      for (int k = 0; k < 3; ++k) vt_idx[fill[tri[t][k]]++] = 3 * t + k;
  }
  corner_n.resize(3 * n_t);
  edge_smooth.resize(3 * n_t);
  vertex_smooth.assign(x.size(), 1);
  for (int t = 0; t < n_t; ++t)
    for (int k = 0; k < 3; ++k) {
      const int v = tri[t][k];
      Vec3 sum = Vec3::Zero();
      for (int i = vt_ptr[v]; i < vt_ptr[v + 1]; ++i) {
        const int t2 = vt_idx[i] / 3;
        if (face_n[t2].dot(face_n[t]) >= crease_cos)
          sum += corner_angle(x, tri[t2], vt_idx[i] % 3) * face_n[t2];
        else
          vertex_smooth[v] = 0;
      }
      corner_n[3 * t + k] = sum.normalized();
      edge_smooth[3 * t + k] = face_n[edge_nb[3 * t + k]].dot(face_n[t]) >= crease_cos;
    }
}

}  // namespace

StlSurface::StlSurface(const fs::path& file, double scale)
    : StlSurface(read_stl_file(file, scale), file.string(), scale) {}

StlSurface::StlSurface(std::string_view bytes, const std::string& name, double scale) {
  const SourceLocation where{name, 0, 0, ""};
  check_scale(where, scale);
  const Soup soup = parse_stl(bytes, where, scale);
  const int n_t = static_cast<int>(soup.corners.size() / 3);
  if (n_t == 0) throw InputError(where, "the STL file contains no triangles");
  auto at_triangle = [&](int t) {  // the facet's line in an ASCII file
    return SourceLocation{name, soup.line.empty() ? 0 : soup.line[t], 0, ""};
  };
  weld(soup, x_, tri_);
  face_n_ = face_normals(x_, tri_, at_triangle);

  Vec3 lo = x_[0], hi = x_[0];
  for (const Vec3& x : x_) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  size_ = (hi - lo).norm();

  build_topology(name, soup.line);

  volume_ = enclosed_volume(x_, tri_);
  if (std::abs(volume_) <= round_off * size_ * size_ * size_)
    throw InputError(where, "the surface encloses no volume; a rigid body must be a solid");
  if (volume_ < 0)
    throw InputError(where, fmt::format("the triangle normals point inward (the volume enclosed "
                                        "by the surface, taken with the vertex order, is {:.6g} "
                                        "< 0): reverse the vertex order of every triangle so that "
                                        "it is counter-clockwise seen from outside the body",
                                        volume_));

  pseudo_normals(x_, tri_, face_n_, edge_nb_, edge_n_, vertex_n_);
  smoothed_normals(x_, tri_, face_n_, edge_nb_, corner_n_, edge_smooth_, vertex_smooth_);

  // Bounding-volume hierarchy: median split of the centroids along their longest extent.
  std::vector<Vec3> centroid(n_t);
  for (int t = 0; t < n_t; ++t)
    centroid[t] = (x_[tri_[t][0]] + x_[tri_[t][1]] + x_[tri_[t][2]]) / 3;
  order_.resize(n_t);
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * static_cast<std::size_t>(n_t));
  build_node(centroid, 0, n_t);
}

void StlSurface::build_topology(const std::string& name, const std::vector<int>& facet_line) {
  auto at_triangle = [&](int t) {
    return SourceLocation{name, facet_line.empty() ? 0 : facet_line[t], 0, ""};
  };
  // Half-edges sorted by their undirected edge: a closed, consistently oriented surface has
  // each edge exactly twice, once in each direction.
  const int n_t = n_triangles();
  std::vector<std::pair<std::uint64_t, int>> half(3 * n_t);  // (edge key, 3 t + k)
  for (int t = 0; t < n_t; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto i = static_cast<std::uint64_t>(tri_[t][k]);
      const auto j = static_cast<std::uint64_t>(tri_[t][(k + 1) % 3]);
      half[3 * t + k] = {std::min(i, j) << 32 | std::max(i, j), 3 * t + k};
    }
  std::sort(half.begin(), half.end());
  edge_nb_.assign(3 * n_t, -1);
  int n_open = 0, n_shared = 0, n_same = 0;
  int bad = -1, bad_count = 0, same = -1;  // first offender of each kind, as an index into half
  for (std::size_t i = 0, j = 0; i < half.size(); i = j) {
    while (j < half.size() && half[j].first == half[i].first) ++j;
    const int count = static_cast<int>(j - i);
    if (count != 2) {
      (count == 1 ? n_open : n_shared)++;
      if (bad < 0) bad = static_cast<int>(i), bad_count = count;
      continue;
    }
    const int h0 = half[i].second, h1 = half[i + 1].second;
    if (tri_[h0 / 3][h0 % 3] == tri_[h1 / 3][h1 % 3]) {
      if (n_same++ == 0) same = static_cast<int>(i);
      continue;
    }
    edge_nb_[h0] = h1 / 3;
    edge_nb_[h1] = h0 / 3;
  }
  auto edge_str = [&](int h) {
    const int t = h / 3, k = h % 3;
    return fmt::format("from {} to {}", point_str(x_[tri_[t][k]]),
                       point_str(x_[tri_[t][(k + 1) % 3]]));
  };
  if (bad >= 0) {
    const int h = half[bad].second;
    throw InputError(
        at_triangle(h / 3),
        fmt::format("the surface is not closed: the edge {} belongs to {} triangle{} (triangle "
                    "{}); in all {} edge{} belong to one triangle only and {} to more than two. "
                    "A rigid body must be a closed surface in which every edge joins exactly two "
                    "triangles (no holes, gaps, T-junctions or duplicate triangles): repair the "
                    "STL, e.g. with MeshLab or admesh",
                    edge_str(h), bad_count, bad_count == 1 ? "" : "s", h / 3 + 1, n_open,
                    n_open == 1 ? "" : "s", n_shared));
  }
  if (n_same > 0) {
    const int h0 = half[same].second, h1 = half[same + 1].second;
    throw InputError(
        at_triangle(h1 / 3),
        fmt::format("the triangles are inconsistently oriented: triangles {} and {} both run "
                    "along the edge {} in the same direction ({} such edge{} in all). Order the "
                    "vertices of every triangle counter-clockwise seen from outside the body "
                    "(right-hand rule, normal pointing out), e.g. with MeshLab's 'Re-Orient all "
                    "faces coherently'",
                    h0 / 3 + 1, h1 / 3 + 1, edge_str(h0), n_same, n_same == 1 ? "" : "s"));
  }
}

int StlSurface::build_node(const std::vector<Vec3>& centroid, int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Vec3 lo = Vec3::Constant(inf), hi = Vec3::Constant(-inf);
  Vec3 c_lo = lo, c_hi = hi;
  for (int i = begin; i < end; ++i) {
    const int t = order_[i];
    for (const int v : tri_[t]) lo = lo.cwiseMin(x_[v]), hi = hi.cwiseMax(x_[v]);
    c_lo = c_lo.cwiseMin(centroid[t]), c_hi = c_hi.cwiseMax(centroid[t]);
  }
  nodes_[id].lo = lo;
  nodes_[id].hi = hi;
  if (end - begin <= leaf_size) {
    nodes_[id].index = begin;
    nodes_[id].count = end - begin;
    return id;
  }
  int axis = 0;
  (c_hi - c_lo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) { return centroid[a][axis] < centroid[b][axis]; });
  build_node(centroid, begin, mid);
  nodes_[id].index = build_node(centroid, mid, end);
  return id;
}

StlSurface::Closest StlSurface::closest(const Vec3& p, int* n_tested) const {
  // Branch and bound: nearer child first, and no box farther than the best triangle so far.
  // Median splits keep the depth below 32, so the stack (depth + 1 entries) cannot overflow.
  struct Entry {
    int node;
    double d2;
  };
  std::array<Entry, 64> stack;
  int top = 0;
  stack[top++] = {0, box_distance2(nodes_[0].lo, nodes_[0].hi, p)};
  Closest best;
  best.d2 = inf;
  int tested = 0;
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best.d2) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (int i = node.index; i < node.index + node.count; ++i) {
        const int t = order_[i];
        const TrianglePoint q =
            closest_on_triangle(p, x_[tri_[t][0]], x_[tri_[t][1]], x_[tri_[t][2]]);
        const double d2 = (p - q.x).squaredNorm();
        ++tested;
        if (d2 < best.d2) best = {q.x, d2, t, static_cast<Feature>(q.feature)};
      }
      continue;
    }
    Entry near{e.node + 1, box_distance2(nodes_[e.node + 1].lo, nodes_[e.node + 1].hi, p)};
    Entry far{node.index, box_distance2(nodes_[node.index].lo, nodes_[node.index].hi, p)};
    if (far.d2 < near.d2) std::swap(near, far);
    // assert, not HENCKY_VERIFY: this is the innermost loop of every contact query (a check
    // per box visited), and the depth bound above makes it a debug-build check.
    assert(top + 2 <= static_cast<int>(stack.size()));
    if (far.d2 < best.d2) stack[top++] = far;
    if (near.d2 < best.d2) stack[top++] = near;
  }
  if (n_tested) *n_tested = tested;
  return best;
}

const Vec3& StlSurface::pseudo_normal(const Closest& c) const {
  const int f = static_cast<int>(c.f);
  if (f == 0) return face_n_[c.t];
  if (f <= 3) return edge_n_[3 * c.t + f - 1];
  return vertex_n_[tri_[c.t][f - 4]];
}

double StlSurface::signed_distance(const Vec3& p) const {
  // Bærentzen and Aanæs 2005, theorem 1: p is outside iff (p - x)·n > 0, with n the
  // angle-weighted pseudo-normal of the face, edge or vertex the closest point x lies on.
  const Closest c = closest(p, nullptr);
  const double d = std::sqrt(c.d2);
  return (p - c.x).dot(pseudo_normal(c)) < 0 ? -d : d;
}

SurfacePoint StlSurface::nearest(const Vec3& p) const {
  const Closest c = closest(p, nullptr);
  SurfacePoint s{c.x, pseudo_normal(c)};
  // On a smooth part of the body (no crease at the feature the point lies on), the normal is
  // the corner normals interpolated at the point: it turns continuously across the facets
  // instead of jumping by their angle, which kept the contact iteration of nodes near facet
  // edges from settling (a faceted sphere needed 16 iterations a step where the analytic one
  // needed 7, and stalled on coarser facets).
  const int f = static_cast<int>(c.f);
  const bool smooth = f == 0 || (f <= 3 ? edge_smooth_[3 * c.t + f - 1] != 0
                                        : vertex_smooth_[tri_[c.t][f - 4]] != 0);
  if (smooth) {
    const auto& tri = tri_[c.t];
    const Vec3 area = (x_[tri[1]] - x_[tri[0]]).cross(x_[tri[2]] - x_[tri[0]]);
    const double inv = 1 / area.squaredNorm();
    Vec3 n = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = x_[tri[(k + 1) % 3]];
      const Vec3& b = x_[tri[(k + 2) % 3]];
      const double w = (b - a).cross(c.x - a).dot(area) * inv;  // barycentric weight of corner k
      n += std::clamp(w, 0.0, 1.0) * corner_n_[3 * c.t + k];
    }
    s.n = n.normalized();
    return s;
  }
  // Off an edge or a vertex, the normal of the distance field is the direction from x to p
  // (outward: flipped inside); on the surface only the pseudo-normal is defined.
  if (c.f != Feature::face && c.d2 > std::pow(direction_floor * size_, 2)) {
    const Vec3 u = (p - c.x) / std::sqrt(c.d2);
    s.n = u.dot(s.n) < 0 ? Vec3(-u) : u;
  }
  return s;
}

int StlSurface::n_triangles_tested(const Vec3& p) const {
  int n = 0;
  closest(p, &n);
  return n;
}

std::optional<SurfacePoint> StlSurface::intersection(const Vec3& a, const Vec3& b) const {
  const Vec3 d = b - a;
  const double length = d.norm();
  if (!(length > 0)) return std::nullopt;
  const double pad = round_off * size_;
  double best_s = inf;
  int best_t = -1;

  // Whether a segment entering triangle t at barycentric weights w (near edge k when the
  // weight of the opposite corner is ~0) really goes inside: across a convex edge the body is
  // below both faces, so a segment that enters t's plane but not the neighbour's only grazes.
  auto grazes_convex_edge = [&](int t, const Vec3& w) {
    for (int k = 0; k < 3; ++k) {
      if (w[(k + 2) % 3] > barycentric_tol) continue;
      const int nb = edge_nb_[3 * t + k];
      const auto& tn = tri_[nb];
      const int i = tri_[t][k], j = tri_[t][(k + 1) % 3];
      const int opposite =
          tn[0] != i && tn[0] != j ? tn[0] : (tn[1] != i && tn[1] != j ? tn[1] : tn[2]);
      const bool convex = (x_[opposite] - x_[i]).dot(face_n_[t]) < -pad;
      if (convex && d.dot(face_n_[nb]) >= -parallel_tol * length) return true;
    }
    return false;
  };

  std::array<int, 64> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (segment_box_entry(node.lo, node.hi, pad, a, d, std::min(best_s, 1.0)) == inf) continue;
    if (node.count == 0) {
      // assert, not HENCKY_VERIFY: the innermost loop of the query, as in closest().
      assert(top + 2 <= static_cast<int>(stack.size()));
      stack[top++] = node.index;
      stack[top++] = static_cast<int>(&node - nodes_.data()) + 1;
      continue;
    }
    for (int i = node.index; i < node.index + node.count; ++i) {
      const int t = order_[i];
      const Vec3& n = face_n_[t];
      // Height of a above the plane and the rate the segment goes down through it; only
      // entering crossings (speed > 0) count.
      const double speed = -d.dot(n);
      if (speed <= parallel_tol * length) continue;
      const Vec3& v0 = x_[tri_[t][0]];
      const double height = (a - v0).dot(n);
      if (height < -pad || height - speed > pad) continue;  // a below or b above the plane
      // A start within round-off of the plane is on it: the segment enters at a exactly.
      const double s = height <= pad ? 0.0 : std::min(height / speed, 1.0);
      if (s > best_s) continue;
      // Barycentric weights of the crossing from the signed areas it makes with the edges.
      const Vec3 x = a + s * d;
      const Vec3& v1 = x_[tri_[t][1]];
      const Vec3& v2 = x_[tri_[t][2]];
      const Vec3 area = (v1 - v0).cross(v2 - v0);
      const double inv = 1 / area.squaredNorm();
      const Vec3 w{(v2 - v1).cross(x - v1).dot(area) * inv, (v0 - v2).cross(x - v2).dot(area) * inv,
                   (v1 - v0).cross(x - v0).dot(area) * inv};
      if (w.minCoeff() < -barycentric_tol || grazes_convex_edge(t, w)) continue;
      if (s < best_s) best_s = s, best_t = t;
    }
  }
  if (best_t < 0) return std::nullopt;
  return SurfacePoint{a + best_s * d, face_n_[best_t]};
}

std::unique_ptr<RigidSurface> make_stl_surface(const fs::path& file, double scale) {
  return std::make_unique<StlSurface>(file, scale);
}

SurfaceDeclaration stl_mesh_declaration() {
  using Kind = SurfaceKey::Kind;
  return {.name = "mesh",
          .noun = "an STL body",
          .keys = {{.name = "file",
                    .kind = Kind::file,
                    .description = "a closed triangulated body in STL (ASCII or binary)",
                    .example = "body.stl",
                    .file_kind = "STL file"},
                   {.name = "scale",
                    .kind = Kind::positive,
                    .description = "a factor on the STL coordinates",
                    .example = "1",
                    .fallback = 1.0}},
          .make = [](const SurfaceParameters& p) {
            return make_stl_surface(p.path("file"), p.number("scale"));
          }};
}

}  // namespace hencky
