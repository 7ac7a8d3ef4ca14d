#pragma once
// A closed triangulated rigid body read from an STL file (ASCII or binary), behind the
// RigidSurface interface. The triangles are welded at equal coordinates, checked to bound a
// solid (closed, consistently and outward oriented) and indexed by a bounding-volume
// hierarchy, so the queries cost O(log n) triangle tests rather than n.
//
// Signs and normals at edges and vertices use the angle-weighted pseudo-normals of
// J. A. Bærentzen and H. Aanæs, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 11(3), 2005: with them the sign of (p - x)·n is the side of p even
// where the nearest point x is an edge or a vertex of a concave part.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "contact/rigid_surface.hpp"

namespace hencky {

class StlSurface : public RigidSurface {
 public:
  /// Reads `file` (coordinates multiplied by `scale` > 0), welds, validates and indexes it.
  /// Throws InputError naming the file (and the line of an ASCII file) when the file cannot be
  /// read or does not describe a closed, outward-oriented triangulated solid.
  explicit StlSurface(const std::filesystem::path& file, double scale = 1.0);
  /// The same from the bytes of an STL file; `name` is the file in messages (the fuzz target,
  /// fuzz/fuzz_stl.cpp, goes through this one).
  StlSurface(std::string_view bytes, const std::string& name, double scale);

  double signed_distance(const Vec3& p) const override;
  /// The normal is the facets' own at creases (dihedral angles above 30°) and interpolated
  /// from smoothed corner normals elsewhere, so that it turns continuously over a faceted
  /// smooth surface (a sphere) as the true surface's normal does.
  SurfacePoint nearest(const Vec3& p) const override;
  std::optional<SurfacePoint> intersection(const Vec3& a, const Vec3& b) const override;

  /// Triangles and distinct (welded) vertices of the surface.
  int n_triangles() const { return static_cast<int>(tri_.size()); }
  int n_vertices() const { return static_cast<int>(x_.size()); }
  /// Vertex indices of triangle t, counter-clockwise seen from outside, in file order.
  const std::array<int, 3>& triangle(int t) const { return tri_[t]; }
  const Vec3& vertex(int i) const { return x_[i]; }
  /// Volume enclosed by the surface (> 0).
  double volume() const { return volume_; }
  /// Corners of the axis-aligned bounding box.
  const Vec3& box_min() const { return nodes_.front().lo; }
  const Vec3& box_max() const { return nodes_.front().hi; }
  /// Diagnostic: how many triangles the nearest-point search for p examines (the index at
  /// work shows as a number far below n_triangles()).
  int n_triangles_tested(const Vec3& p) const;

 private:
  /// Where on a triangle its closest point lies: the face, edge k (from corner k to k+1), or
  /// corner k.
  enum class Feature : std::uint8_t { face, edge0, edge1, edge2, vertex0, vertex1, vertex2 };
  struct Closest {
    Vec3 x = Vec3::Zero();
    double d2 = 0;  ///< squared distance |p - x|^2
    int t = -1;     ///< triangle
    Feature f = Feature::face;
  };
  /// Bounding-volume hierarchy node in depth-first order: an inner node's first child is the
  /// next node, its second child is `index`; a leaf holds order_[index, index + count).
  struct Node {
    Vec3 lo, hi;
    int index = 0;
    int count = 0;  ///< triangles of a leaf, 0 for an inner node
  };

  void build_topology(const std::string& name, const std::vector<int>& facet_line);
  int build_node(const std::vector<Vec3>& centroid, int begin, int end);
  Closest closest(const Vec3& p, int* n_tested) const;
  /// Angle-weighted pseudo-normal of the feature a closest point lies on.
  const Vec3& pseudo_normal(const Closest& c) const;

  std::vector<Vec3> x_;                  // welded vertices
  std::vector<std::array<int, 3>> tri_;  // vertex indices per triangle
  std::vector<Vec3> face_n_;             // unit outward normal per triangle
  std::vector<Vec3> edge_n_;             // pseudo-normal of edge k of triangle t at 3t + k
  std::vector<int> edge_nb_;             // triangle across edge k of triangle t at 3t + k
  std::vector<Vec3> vertex_n_;           // pseudo-normal per vertex
  std::vector<Vec3> corner_n_;           // smoothed normal of corner k of triangle t at 3t + k
  std::vector<std::uint8_t> edge_smooth_;    // edge k of triangle t is no crease, at 3t + k
  std::vector<std::uint8_t> vertex_smooth_;  // no crease meets at the vertex
  std::vector<Node> nodes_;
  std::vector<int> order_;  // triangles in leaf order
  double volume_ = 0;
  double size_ = 0;  // bounding-box diagonal: the length the tolerances are relative to
};

/// Reads a closed triangulated rigid body from an STL file; see StlSurface.
std::unique_ptr<RigidSurface> make_stl_surface(const std::filesystem::path& file,
                                               double scale = 1.0);

}  // namespace hencky
