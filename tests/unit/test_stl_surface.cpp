// Triangulated rigid bodies from STL: distances, nearest points, normals and segment entries
// against closed forms (a cube exactly, an L-shaped prism exactly, a sphere within the chord
// bound of its icosphere), the spatial index against brute force, and every input error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "contact/stl_surface.hpp"
#include "core/error.hpp"
#include "stl_support.hpp"

namespace fs = std::filesystem;
using namespace hencky;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("hencky-stl-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Orients t counter-clockwise seen from outside, for a body convex about `inside`.
StlTriangle outward(StlTriangle t, const Vec3& inside) {
  if ((t[1] - t[0]).cross(t[2] - t[0]).dot(t[0] - inside) < 0) std::swap(t[1], t[2]);
  return t;
}

/// The box [lo, hi] as 12 triangles, two per face.
std::vector<StlTriangle> box_triangles(const Vec3& lo, const Vec3& hi) {
  auto corner = [&](int i) {
    return Vec3(i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
  };
  // Each face as a cycle of corner numbers (bit j set: coordinate j at hi).
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  const Vec3 mid = (lo + hi) / 2;
  std::vector<StlTriangle> t;
  for (const auto& f : faces) {
    t.push_back(outward({corner(f[0]), corner(f[1]), corner(f[2])}, mid));
    t.push_back(outward({corner(f[0]), corner(f[2]), corner(f[3])}, mid));
  }
  return t;
}

// Closed forms of the unit cube [0, 1]^3.
double cube_distance(const Vec3& p) {
  const Vec3 q = (p - Vec3::Constant(0.5)).cwiseAbs() - Vec3::Constant(0.5);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}
SurfacePoint cube_nearest(const Vec3& p) {
  const Vec3 clamped = p.cwiseMax(0.0).cwiseMin(1.0);
  if (clamped != p) return {clamped, (p - clamped).normalized()};
  int i = 0;
  (p - Vec3::Constant(0.5)).cwiseAbs().maxCoeff(&i);  // the nearest face is normal to i
  SurfacePoint s{p, Vec3::Zero()};
  s.x[i] = p[i] < 0.5 ? 0 : 1;
  s.n[i] = p[i] < 0.5 ? -1 : 1;
  return s;
}

void expect_near(const Vec3& a, const Vec3& b, double tol, const std::string& what) {
  EXPECT_LE((a - b).norm(), tol) << what << ": " << a.transpose() << " vs " << b.transpose();
}

void check_cube(const StlSurface& s, const Vec3& p) {
  const std::string at = "at (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                         std::to_string(p[2]) + ")";
  const SurfacePoint want = cube_nearest(p), got = s.nearest(p);
  EXPECT_NEAR(s.signed_distance(p), cube_distance(p), 1e-12) << at;
  expect_near(got.x, want.x, 1e-12, "nearest point " + at);
  expect_near(got.n, want.n, 1e-12, "normal " + at);
  EXPECT_EQ(s.side(p), cube_distance(p) < 0 ? -1 : 1) << at;
}

class StlCube : public ::testing::TestWithParam<bool> {};  // parameter: binary file

TEST_P(StlCube, MatchesTheAnalyticBox) {
  const fs::path dir = fresh_dir("cube");
  const fs::path file = dir / "cube.stl";
  write_stl(file, box_triangles(Vec3::Zero(), Vec3::Ones()), GetParam());
  const StlSurface s(file);
  EXPECT_EQ(s.n_triangles(), 12);
  EXPECT_EQ(s.n_vertices(), 8);  // welded
  EXPECT_NEAR(s.volume(), 1.0, 1e-14);

  // Near faces, edges and corners, inside and outside; points above face diagonals (a
  // shared edge of two coplanar triangles) included.
  for (const Vec3& p :
       {Vec3(0.5, 0.3, 1.2), Vec3(0.5, 0.3, 0.9), Vec3(0.3, 0.3, 1.5), Vec3(0.3, 0.7, -0.5),
        Vec3(1.3, 0.5, 1.4), Vec3(-0.1, -0.3, 0.5), Vec3(1.1, 1.2, 1.2), Vec3(-0.2, -0.2, -0.2),
        Vec3(1.2, -0.1, 0.3), Vec3(0.95, 0.5, 0.9), Vec3(0.02, 0.03, 0.04), Vec3(0.97, 0.96, 0.98)})
    check_cube(s, p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    // Inside, skip points nearly equidistant from two faces (the nearest point jumps there).
    std::array<double, 3> q;
    for (int j = 0; j < 3; ++j) q[j] = std::abs(p[j] - 0.5);
    std::sort(q.begin(), q.end());
    if (cube_distance(p) < 0 && q[2] - q[1] < 1e-9) continue;
    check_cube(s, p);
  }

  // On the surface: distance 0, side +1, and the pseudo-normal at an edge and at a corner.
  // The corner's angle-weighted normal is (1, 1, 1)/sqrt 3 however the faces are split.
  EXPECT_NEAR(s.signed_distance(Vec3(0.5, 0.5, 1)), 0, 1e-15);
  EXPECT_EQ(s.side(Vec3(0.5, 0.5, 1)), 1);
  expect_near(s.nearest(Vec3(1, 0.5, 1)).n, Vec3(1, 0, 1).normalized(), 1e-12, "edge");
  expect_near(s.nearest(Vec3(1, 1, 1)).n, Vec3(1, 1, 1).normalized(), 1e-12, "corner");
  expect_near(s.nearest(Vec3(0, 0, 1)).n, Vec3(-1, -1, 1).normalized(), 1e-12, "corner");
  EXPECT_NEAR(s.signed_distance(Vec3(0.5, 0.5, 0.5)), -0.5, 1e-15);  // equidistant centre
}

TEST_P(StlCube, SegmentEntries) {
  const fs::path dir = fresh_dir("cube-segments");
  const fs::path file = dir / "cube.stl";
  write_stl(file, box_triangles(Vec3::Zero(), Vec3::Ones()), GetParam());
  const StlSurface s(file);
  auto enters = [&](const Vec3& a, const Vec3& b, const Vec3& x, const Vec3& n) {
    const auto hit = s.intersection(a, b);
    ASSERT_TRUE(hit) << a.transpose() << " -> " << b.transpose();
    expect_near(hit->x, x, 1e-12, "entry point");
    expect_near(hit->n, n, 1e-12, "entry normal");
  };
  auto misses = [&](const Vec3& a, const Vec3& b) {
    EXPECT_FALSE(s.intersection(a, b)) << a.transpose() << " -> " << b.transpose();
  };
  enters({0.3, 0.6, 2}, {0.3, 0.6, 0.5}, {0.3, 0.6, 1}, {0, 0, 1});
  enters({0.3, 0.6, 2}, {0.3, 0.6, -1}, {0.3, 0.6, 1}, {0, 0, 1});   // the first crossing
  enters({0.5, 0.5, -3}, {0.5, 0.5, 1}, {0.5, 0.5, 0}, {0, 0, -1});  // on a face diagonal
  enters({0.25, 0.25, 2}, {0.25, 0.25, 0}, {0.25, 0.25, 1}, {0, 0, 1});
  enters({0.75, 0.25, 2}, {0.75, 0.25, 0}, {0.75, 0.25, 1}, {0, 0, 1});
  const auto corner = s.intersection({2, 2, 2}, {0.5, 0.5, 0.5});  // through a vertex
  ASSERT_TRUE(corner);
  expect_near(corner->x, Vec3(1, 1, 1), 1e-12, "corner entry");
  enters({0.5, 0.5, 1}, {0.5, 0.5, 0.5}, {0.5, 0.5, 1}, {0, 0, 1});  // starts on the surface
  const auto from_edge = s.intersection({1, 0.5, 1}, {0.5, 0.5, 0.5});
  ASSERT_TRUE(from_edge);
  EXPECT_EQ(from_edge->x, Vec3(1, 0.5, 1));
  misses({0.5, 0.5, 0.5}, {0.5, 0.5, 2});    // leaves
  misses({0.2, 0.2, 0.2}, {0.8, 0.7, 0.6});  // stays inside
  misses({2, 2, 2}, {3, 1, 2});              // stays outside
  misses({0.2, 0.5, 1}, {0.8, 0.5, 1});      // slides on a face
  misses({1, 0.5, 1}, {0.5, 0.5, 1});        // from an edge along a face
  misses({2, 0.5, 0}, {0, 0.5, 2});          // touches the edge x = z = 1 and goes on outside
  misses({3, 0.5, 0}, {0, 0.5, 1.5});
  misses({1, 1, 1}, {1, 1, 1});  // no segment
}

INSTANTIATE_TEST_SUITE_P(Stl, StlCube, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "binary" : "ascii"; });

// The L-shaped prism: the polygon below extruded over z in [0, 1]; concave edge along
// x = y = 1.
const std::vector<Vec3> l_polygon = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0},
                                     {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};

/// The polygon (counter-clockwise, z = 0) extruded over z in [0, 1]; each cap is split into
/// the given convex parts, each a fan from its first vertex.
std::vector<StlTriangle> prism_triangles(const std::vector<Vec3>& polygon,
                                         const std::vector<std::vector<int>>& convex_parts) {
  const Vec3 up = Vec3::UnitZ();
  const int n = static_cast<int>(polygon.size());
  std::vector<StlTriangle> t;
  for (const auto& part : convex_parts)
    for (std::size_t i = 1; i + 1 < part.size(); ++i) {
      const Vec3 &a = polygon[part[0]], &b = polygon[part[i]], &c = polygon[part[i + 1]];
      t.push_back({a + up, b + up, c + up});
      t.push_back({a, c, b});
    }
  // Walls: outward to the right of each counter-clockwise polygon edge.
  for (int i = 0; i < n; ++i) {
    const Vec3 &a = polygon[i], &b = polygon[(i + 1) % n];
    t.push_back({a, b, b + up});
    t.push_back({a, b + up, a + up});
  }
  return t;
}

std::vector<StlTriangle> l_prism_triangles() {
  return prism_triangles(l_polygon, {{3, 4, 5, 0, 1, 2}});
}

double segment_distance_2d(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 q(p[0], p[1], 0);
  const double s = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (q - a - s * (b - a)).norm();
}

/// Exact signed distance to the L prism: outside, the distance to the nearer of the two boxes
/// whose union it is; inside, the distance to the nearest wall (a 2D polygon distance) or cap.
double l_prism_distance(const Vec3& p) {
  auto box = [&](const Vec3& lo, const Vec3& hi) {
    return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm();
  };
  const double outside = std::min(box({0, 0, 0}, {2, 1, 1}), box({0, 0, 0}, {1, 2, 1}));
  if (outside > 0) return outside;
  double d = std::min(p[2], 1 - p[2]);
  for (int i = 0; i < 6; ++i)
    d = std::min(d, segment_distance_2d(p, l_polygon[i], l_polygon[(i + 1) % 6]));
  return -d;
}

TEST(StlConcave, LPrismSignsAndEntries) {
  const fs::path dir = fresh_dir("l-prism");
  const fs::path file = dir / "l.stl";
  write_stl(file, l_prism_triangles(), false);
  const StlSurface s(file);
  EXPECT_NEAR(s.volume(), 3.0, 1e-14);

  // Inside near the concave edge the nearest point is on the edge, and so is the normal.
  EXPECT_NEAR(s.signed_distance({0.9, 0.9, 0.5}), -std::sqrt(0.02), 1e-12);
  expect_near(s.nearest({0.9, 0.9, 0.5}).x, Vec3(1, 1, 0.5), 1e-12, "concave edge point");
  expect_near(s.nearest({0.9, 0.9, 0.5}).n, Vec3(1, 1, 0).normalized(), 1e-12, "concave edge");
  EXPECT_NEAR(s.signed_distance({0.95, 0.8, 0.5}), -std::hypot(0.05, 0.2), 1e-12);
  // Outside in the notch, and at a convex edge next to the saddle vertex (1, 1, 1).
  EXPECT_NEAR(s.signed_distance({1.2, 1.1, 0.5}), 0.1, 1e-12);
  expect_near(s.nearest({1.2, 1.1, 0.5}).n, Vec3(0, 1, 0), 1e-12, "notch wall");
  EXPECT_NEAR(s.signed_distance({1.05, 1.05, 0.5}), 0.05, 1e-12);  // on the bisector
  EXPECT_NEAR(s.signed_distance({1.2, 1.1, 1.05}), std::hypot(0.1, 0.05), 1e-12);
  expect_near(s.nearest({1.2, 1.1, 1.05}).n, Vec3(0, 2, 1).normalized(), 1e-12, "convex edge");
  EXPECT_NEAR(s.signed_distance({0.95, 0.9, 0.95}), -0.05, 1e-12);
  // The pseudo-normal on the concave edge itself bisects the two walls, out into the notch.
  expect_near(s.nearest({1, 1, 0.5}).n, Vec3(1, 1, 0).normalized(), 1e-12, "on concave edge");

  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 2.5), uz(-0.5, 1.5);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(u(rng), u(rng), uz(rng));
    EXPECT_NEAR(s.signed_distance(p), l_prism_distance(p), 1e-12) << p.transpose();
  }

  // A segment through both arms enters twice; the first entry counts.
  auto hit = s.intersection({0.2, 2.5, 0.5}, {2.5, 0.2, 0.5});
  ASSERT_TRUE(hit);
  expect_near(hit->x, Vec3(0.7, 2, 0.5), 1e-12, "first entry");
  expect_near(hit->n, Vec3(0, 1, 0), 1e-12, "first entry normal");
  hit = s.intersection({2.5, 0.2, 0.5}, {0.2, 2.5, 0.5});
  ASSERT_TRUE(hit);
  expect_near(hit->x, Vec3(2, 0.7, 0.5), 1e-12, "first entry, reversed");
  // From the notch into the concave edge: it goes inside there.
  hit = s.intersection({1.5, 1.5, 0.5}, {0.5, 0.5, 0.5});
  ASSERT_TRUE(hit);
  expect_near(hit->x, Vec3(1, 1, 0.5), 1e-12, "concave edge entry");
}

/// The chord bound of a sphere mesh with its vertices on (or, in float32, next to) the sphere:
/// the mesh lies between radius r - h and r + h, so distances to mesh and sphere differ by at
/// most h, and a face normal is within angle theta of the radius through any of its points.
struct SphereBound {
  double h = 0, theta = 0;
};
SphereBound chord_bound(const StlSurface& s, const Vec3& c, double r) {
  SphereBound b;
  double cos_min = 1;
  for (int t = 0; t < s.n_triangles(); ++t) {
    const auto& v = s.triangle(t);
    const Vec3 &a = s.vertex(v[0]), &p = s.vertex(v[1]), &q = s.vertex(v[2]);
    const Vec3 n = (p - a).cross(q - a).normalized();
    for (const Vec3& x : {a, p, q}) {
      b.h = std::max(b.h, std::abs((x - c).norm() - r));
      cos_min = std::min(cos_min, n.dot((x - c).normalized()));
    }
    b.h = std::max(b.h, r - (a - c).dot(n));  // the plane is the face's closest part to c
  }
  b.theta = std::acos(cos_min);
  return b;
}

double angle(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(StlIcosphere, MatchesTheSphereWithinTheChordBound) {
  const fs::path dir = fresh_dir("icosphere");
  const fs::path file = dir / "ball.stl";
  const Vec3 c(0.1, -0.2, 0.3);
  const double r = 1;
  write_icosphere_stl(file, c, r, 4, false);
  const StlSurface s(file);
  ASSERT_EQ(s.n_triangles(), 5120);
  EXPECT_EQ(s.n_vertices(), 2562);
  const SphereBound b = chord_bound(s, c, r);
  EXPECT_LT(b.h, 2e-3);
  EXPECT_NEAR(s.volume(), 4 * std::numbers::pi / 3, 4 * std::numbers::pi * b.h);

  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> radius(0.75, 2.0);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
    const double rho = radius(rng);
    const Vec3 p = c + rho * dir;
    const double d = s.signed_distance(p);
    EXPECT_NEAR(d, rho - r, b.h + 1e-12) << p.transpose();
    if (std::abs(rho - r) > b.h) {
      EXPECT_EQ(s.side(p), rho > r ? 1 : -1);
    }
    const SurfacePoint x = s.nearest(p);
    EXPECT_NEAR((p - x.x).norm(), std::abs(d), 1e-12);
    EXPECT_NEAR((x.x - c).norm(), r, b.h + 1e-12);
    EXPECT_NEAR(x.n.norm(), 1, 1e-12);
    // Outside, n is in the normal cone at x, within theta of the radius through x and p;
    // inside (depth d < 0.25 + h), the radius through p turns from that through x by at most
    // another d / (|x| - d) theta < 0.3/0.7 theta.
    EXPECT_LE(angle(x.n, dir), (rho > r ? 1 : 1 + 0.3 / 0.7) * b.theta + 1e-9) << p.transpose();
  }

  // Segments from outside towards the centre enter at the radius.
  for (int i = 0; i < 300; ++i) {
    const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
    const Vec3 a = c + radius(rng) * 1.5 * dir;
    const auto hit = s.intersection(a, c);
    ASSERT_TRUE(hit) << a.transpose();
    EXPECT_NEAR((hit->x - c).norm(), r, b.h + 1e-12);
    EXPECT_LE(angle(hit->n, dir), b.theta + 1e-9);
    EXPECT_NEAR((hit->x - a).cross(c - a).norm(), 0, 1e-12);  // on the segment
  }
  EXPECT_FALSE(s.intersection(c + Vec3(2, 0, 0), c + Vec3(0, 2, 0)));        // misses
  EXPECT_FALSE(s.intersection(c + Vec3(0.3, 0, 0), c + Vec3(0, 0.5, 0.2)));  // inside
  EXPECT_FALSE(s.intersection(c, c + Vec3(0.5, 2, -1)));                     // leaves
  // Starting on the surface (a vertex, a face centre, an edge midpoint) and going inward.
  const auto& t0 = s.triangle(100);
  for (const Vec3& a :
       {s.vertex(t0[0]), Vec3((s.vertex(t0[0]) + s.vertex(t0[1]) + s.vertex(t0[2])) / 3),
        Vec3((s.vertex(t0[1]) + s.vertex(t0[2])) / 2)}) {
    const auto hit = s.intersection(a, c);
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->x, a);
  }
}

/// Closest point of a triangle by a different route than the library's: the projection on
/// the plane when it falls inside, else the closest point of the three edges.
Vec3 brute_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 q = p - (p - a).dot(n) * n;
  const auto inside = [&](const Vec3& u, const Vec3& v) {
    return (v - u).cross(q - u).dot(n) >= 0;
  };
  if (inside(a, b) && inside(b, c) && inside(c, a)) return q;
  Vec3 best = a;
  for (const auto& [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
    const double s = std::clamp((p - u).dot(v - u) / (v - u).squaredNorm(), 0.0, 1.0);
    const Vec3 x = u + s * (v - u);
    if ((p - x).squaredNorm() < (p - best).squaredNorm()) best = x;
  }
  return best;
}

/// Distance from p to the surface by looking at every triangle, in file order. Triangles that
/// cannot be nearer than the best so far (|p - corner 0| beyond it by more than the longest
/// edge from that corner) are skipped before the exact test, which makes the reference cheap
/// enough for sanitizer builds without making it depend on any spatial structure.
class BruteForce {
 public:
  explicit BruteForce(const StlSurface& s) : s_(s), reach_(s.n_triangles()) {
    for (int t = 0; t < s.n_triangles(); ++t) {
      const auto& v = s.triangle(t);
      reach_[t] = std::max((s.vertex(v[1]) - s.vertex(v[0])).norm(),
                           (s.vertex(v[2]) - s.vertex(v[0])).norm());
    }
  }
  double distance(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (int t = 0; t < s_.n_triangles(); ++t) {
      const auto& v = s_.triangle(t);
      const Vec3& a = s_.vertex(v[0]);
      const double dx = p[0] - a[0], dy = p[1] - a[1], dz = p[2] - a[2];
      const double bound = best + reach_[t];
      if (dx * dx + dy * dy + dz * dz >= bound * bound) continue;
      best = std::min(best, (p - brute_closest(p, a, s_.vertex(v[1]), s_.vertex(v[2]))).norm());
    }
    return best;
  }

 private:
  const StlSurface& s_;
  std::vector<double> reach_;
};

/// Even-odd rule: whether (p[0], p[1]) is inside the polygon.
bool in_polygon(const std::vector<Vec3>& poly, const Vec3& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec3 &a = poly[i], &b = poly[j];
    if ((a[1] > p[1]) != (b[1] > p[1]) &&
        p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
      in = !in;
  }
  return in;
}

TEST(StlSharp, SignsAtAcuteAndReflexEdgesAndVertices) {
  // A prism with an acute convex edge (45 degrees, at x = 3) and a narrow V notch whose tip
  // (1, 0.2) is a reflex edge of 346 degrees. There the faces' normals are more than 90
  // degrees apart, so the normal of whichever face the nearest point was found on can give
  // the wrong side: only the pseudo-normals are right.
  const std::vector<Vec3> v_polygon = {{0, 0, 0},   {1, 0, 0},   {3, 0, 0},   {2, 1, 0},
                                       {1.1, 1, 0}, {1, 0.2, 0}, {0.9, 1, 0}, {0, 1, 0}};
  const fs::path dir = fresh_dir("sharp");
  const fs::path file = dir / "v.stl";
  write_stl(file, prism_triangles(v_polygon, {{0, 1, 5, 6, 7}, {1, 2, 3, 4, 5}}), false);
  const StlSurface s(file);
  EXPECT_NEAR(s.volume(), 2.5 - 0.08, 1e-14);
  const BruteForce brute(s);

  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3 features[] = {{3, 0, 0.5},   {3, 0, 1},   {3, 0, 0},
                           {1, 0.2, 0.5}, {1, 0.2, 1}, {1, 0.2, 0}};
  int n_inside = 0, n_outside = 0;
  for (int i = 0; i < 6000; ++i) {
    const Vec3 p = i < 5000 ? Vec3(features[i % 6] + 0.15 * Vec3(u(rng), u(rng), u(rng)))
                            : Vec3(1.5 + 2 * u(rng), 0.5 + u(rng), 0.5 + u(rng));
    const bool inside = p[2] > 0 && p[2] < 1 && in_polygon(v_polygon, p);
    const double d = brute.distance(p);
    EXPECT_NEAR(std::abs(s.signed_distance(p)), d, 1e-12) << p.transpose();
    if (d < 1e-9) continue;
    (inside ? n_inside : n_outside)++;
    EXPECT_EQ(s.side(p), inside ? -1 : 1) << p.transpose();
    // The normal points from the surface towards p outside, away from p inside.
    const SurfacePoint x = s.nearest(p);
    EXPECT_NEAR(x.n.dot(p - x.x), inside ? -d : d, 1e-12) << p.transpose();
  }
  EXPECT_GT(n_inside, 1000);
  EXPECT_GT(n_outside, 1000);
}

TEST(StlIndex, LargeMeshMatchesBruteForce) {
  const fs::path dir = fresh_dir("index");
  const fs::path file = dir / "ball6.stl";
  write_icosphere_stl(file, Vec3::Zero(), 1, 6, true);
  const auto t0 = std::chrono::steady_clock::now();
  const StlSurface s(file);
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_EQ(s.n_triangles(), 81920);

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const BruteForce brute(s);
  long tested = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(std::abs(s.signed_distance(p)), brute.distance(p), 1e-12) << p.transpose();
    tested += s.n_triangles_tested(p);
  }
  // The index at work: a query examines a tiny fraction of the triangles.
  EXPECT_LT(tested / 200.0, 0.01 * s.n_triangles());

  // Queries from OpenMP threads (as the contact code makes them) give the serial answers.
  std::vector<Vec3> shared(2000);
  for (Vec3& p : shared) p = Vec3(u(rng), u(rng), u(rng));
  std::vector<double> serial(shared.size()), parallel(shared.size());
  for (std::size_t i = 0; i < shared.size(); ++i) serial[i] = s.signed_distance(shared[i]);
#pragma omp parallel for
  for (int i = 0; i < static_cast<int>(shared.size()); ++i)
    parallel[i] = s.signed_distance(shared[i]);
  EXPECT_EQ(serial, parallel);

  // Speed, reported and not asserted: points anywhere in the box around the ball (those near
  // the centre are almost equidistant from every triangle, the worst case of branch and
  // bound), and points within 0.05 of the surface, as contact queries are. Fewer in
  // unoptimised (sanitizer) builds, where the time means nothing.
#ifdef NDEBUG
  const int n_queries = 10000;
#else
  const int n_queries = 500;
#endif
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> shell(0.95, 1.05);
  for (const bool near_surface : {false, true}) {
    std::vector<Vec3> points(n_queries);
    for (Vec3& p : points)
      p = near_surface ? Vec3(shell(rng) * Vec3(g(rng), g(rng), g(rng)).normalized())
                       : Vec3(u(rng), u(rng), u(rng));
    long n_tested = 0;
    for (int i = 0; i < 200; ++i) n_tested += s.n_triangles_tested(points[i]);
    double sum = 0;
    const auto t2 = std::chrono::steady_clock::now();
    for (const Vec3& p : points) sum += s.nearest(p).x.norm();
    const auto t3 = std::chrono::steady_clock::now();
    EXPECT_GT(sum, 0);
    const double query = std::chrono::duration<double>(t3 - t2).count();
    std::cout << "[ stl     ] " << s.n_triangles() << " triangles, points "
              << (near_surface ? "near the surface" : "in the box") << ": " << n_queries
              << " nearest queries in " << query * 1e3 << " ms (" << n_queries / query
              << " per second), " << n_tested / 200.0 << " triangles tested per query\n";
  }
  std::cout << "[ stl     ] read + index: " << std::chrono::duration<double>(t1 - t0).count() * 1e3
            << " ms\n";
}

TEST(StlFile, BinaryStartingWithSolidAndScale) {
  const fs::path dir = fresh_dir("binary-solid");
  const fs::path file = dir / "mm.stl";
  // A box in millimetres, binary, whose header starts like an ASCII file.
  write_stl(file, box_triangles(Vec3(0, 0, 0), Vec3(1000, 2000, 500)), true,
            "solid box exported in mm");
  {
    std::ifstream in(file, std::ios::binary);
    std::string head(5, ' ');
    in.read(head.data(), 5);
    ASSERT_EQ(head, "solid");
  }
  const StlSurface s(file, 1e-3);
  EXPECT_EQ(s.n_triangles(), 12);
  EXPECT_NEAR(s.volume(), 1.0, 1e-12);
  expect_near(s.box_max(), Vec3(1, 2, 0.5), 1e-15, "scaled box");
  EXPECT_NEAR(s.signed_distance({0.5, 1, 0.75}), 0.25, 1e-12);
  EXPECT_NEAR(s.signed_distance({0.5, 1.9, 0.25}), -0.1, 1e-12);
  const auto any = make_stl_surface(file, 2e-3);  // the factory, through the interface
  EXPECT_NEAR(any->signed_distance({1, 2, 1.5}), 0.5, 1e-12);
}

TEST(StlFile, AsciiWithSeveralSolidsAndCrLf) {
  // Some exporters write one solid per part, and Windows line ends.
  const fs::path dir = fresh_dir("solids");
  const auto cube = box_triangles(Vec3::Zero(), Vec3::Ones());
  std::string text;
  for (const int half : {0, 1}) {
    const fs::path part = dir / ("part" + std::to_string(half) + ".stl");
    write_stl(part, {cube.begin() + 6 * half, cube.begin() + 6 * half + 6}, false);
    std::ifstream in(part);
    for (std::string line; std::getline(in, line);) text += line + "\r\n";
  }
  std::ofstream(dir / "cube.stl", std::ios::binary) << text;
  const StlSurface s(dir / "cube.stl");
  EXPECT_EQ(s.n_triangles(), 12);
  EXPECT_NEAR(s.volume(), 1.0, 1e-14);
}

/// Expects reading `file` to throw an InputError naming the file, containing `phrase`, at
/// `line` when given.
void expect_error(const fs::path& file, const std::string& phrase, int line = -1,
                  double scale = 1) {
  try {
    StlSurface s(file, scale);
    ADD_FAILURE() << "no error reading " << file;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_NE(what.find(phrase), std::string::npos) << "'" << phrase << "' not in: " << what;
    if (line >= 0) {
      EXPECT_EQ(e.where().line, line) << what;
    }
  }
}

TEST(StlErrors, EachBadInputNamesTheFileAndTheProblem) {
  const fs::path dir = fresh_dir("errors");
  const auto cube = box_triangles(Vec3::Zero(), Vec3::Ones());
  auto written = [&](const std::string& name, const std::vector<StlTriangle>& t, bool binary) {
    write_stl(dir / name, t, binary);
    return dir / name;
  };
  auto text = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir / name, std::ios::binary) << content;
    return dir / name;
  };

  expect_error(dir / "missing.stl", "does not exist");
  expect_error(text("empty.stl", ""), "is empty");
  expect_error(text("short.stl", "hello"), "not an STL file");
  expect_error(text("none.stl", "solid x\nendsolid x\n"), "contains no triangles");
  expect_error(written("cube.stl", cube, false), "positive", -1, 0.0);

  auto open = cube;
  open.pop_back();
  expect_error(written("open.stl", open, false), "not closed");
  expect_error(written("open.stl", open, false), "in all 3 edges belong to one triangle only");
  auto doubled = cube;
  doubled.push_back(cube[3]);
  expect_error(written("doubled.stl", doubled, true), "3 to more than two");

  auto flipped = cube;
  std::swap(flipped[4][1], flipped[4][2]);
  expect_error(written("flipped.stl", flipped, false), "inconsistently oriented");
  expect_error(written("flipped.stl", flipped, false), "(3 such edges in all)");

  auto inward = cube;
  for (auto& t : inward) std::swap(t[1], t[2]);
  expect_error(written("inward.stl", inward, true), "normals point inward");
  expect_error(written("inward.stl", inward, true), "reverse the vertex order");

  auto sliver = cube;
  sliver.insert(sliver.begin() + 4, {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5), Vec3(1, 1, 1)});
  // Facet 5 starts on line 2 + 4 * 7 (the "solid" line, then seven lines a facet).
  expect_error(written("sliver.stl", sliver, false), "triangle 5 has zero area", 30);
  expect_error(written("sliver.stl", sliver, true), "triangle 5 has zero area", 0);

  const fs::path binary = written("truncated.stl", cube, true);
  fs::resize_file(binary, fs::file_size(binary) - 10);
  expect_error(binary, "truncated or corrupt binary STL");

  // Malformed ASCII, each reported on its line.
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
      "endfacet\n";
  expect_error(text("coords.stl", "solid a\n" + facet +
                                      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0\n"),
               "expected three numbers after 'vertex'", 12);
  expect_error(text("word.stl", "solid a\n" + facet +
                                    "facet normal 0 0 1\nouter loop\n"
                                    "vertex 0 0 0\nvertex 1 0 abc\n"),
               "found 'abc'", 12);
  expect_error(text("keyword.stl", "solid a\n" + facet + "facet nromal 0 0 1\n"),
               "expected 'normal'", 9);
  expect_error(text("four.stl",
                    "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                    "vertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\n"),
               "expected 'endloop'", 7);
  expect_error(text("cut.stl", "solid a\n" + facet + "facet normal 0 0 1\nouter loop\n"),
               "found the end of the file");
  expect_error(text("nan.stl", "solid a\n" + facet +
                                   "facet normal 0 0 1\nouter loop\n"
                                   "vertex nan 0 0\n"),
               "non-finite coordinate", 11);
}

}  // namespace
