#pragma once
// Rigid surfaces for contact (report section 3): the functions the node algorithm needs,
// nearestPoint(r), intersectionPoint(r1, r2) and side(r), with the outward normal. A surface
// is described in its own frame (the case's coordinates at t = 0); the contact code applies
// the prescribed translation by moving the query points, so the surfaces know nothing of time.
//
// "Outside" is the side of the deformable body: the normal points out of the rigid body,
// towards the body it supports, and side(r) = -1 means r has penetrated the rigid body.
#include <filesystem>
#include <memory>
#include <optional>

#include "core/types.hpp"

namespace hencky {

/// A point of a rigid surface and the unit outward normal there.
struct SurfacePoint {
  Vec3 x = Vec3::Zero();
  Vec3 n = Vec3::UnitZ();
};

class RigidSurface {
 public:
  virtual ~RigidSurface() = default;
  /// Signed distance to the surface: > 0 outside the rigid body, < 0 inside it.
  virtual double signed_distance(const Vec3& p) const = 0;
  /// nearestPoint(p): the point of the surface nearest to p, with the outward normal there.
  /// Where the nearest point is not unique (the centre of a sphere, the axis of a cylinder,
  /// the medial surface of a mesh), one of them.
  virtual SurfacePoint nearest(const Vec3& p) const = 0;
  /// intersectionPoint(a, b): the first point where the segment from a to b enters the rigid
  /// body (crosses the surface from outside to inside, or touches it at a point where it goes
  /// on inside), nullopt when it does not. A segment that starts on the surface and goes
  /// inside enters at a.
  virtual std::optional<SurfacePoint> intersection(const Vec3& a, const Vec3& b) const = 0;
  /// side(p) of the report: -1 inside the rigid body, +1 outside or on the surface.
  int side(const Vec3& p) const { return signed_distance(p) < 0 ? -1 : 1; }
};

/// Half-space below a plane; `normal` points from the rigid body towards the deformable one.
std::unique_ptr<RigidSurface> make_plane(const Vec3& point, const Vec3& normal);
/// A rigid ball; the deformable body stays outside it.
std::unique_ptr<RigidSurface> make_sphere(const Vec3& center, double radius);
/// An infinite rigid cylinder (solid rod) about the line through `point` along `axis`; the
/// deformable body stays outside it.
std::unique_ptr<RigidSurface> make_cylinder(const Vec3& point, const Vec3& axis, double radius);

}  // namespace hencky
