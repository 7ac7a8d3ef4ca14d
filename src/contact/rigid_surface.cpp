#include "contact/rigid_surface.hpp"

#include <cmath>

#include "contact/surface_type.hpp"

namespace hencky {
namespace {

class Plane final : public RigidSurface {
 public:
  Plane(const Vec3& point, const Vec3& normal) : p0_(point), n_(normal.normalized()) {}
  double signed_distance(const Vec3& p) const override { return (p - p0_).dot(n_); }
  SurfacePoint nearest(const Vec3& p) const override {
    return {p - signed_distance(p) * n_, n_};
  }
  std::optional<SurfacePoint> intersection(const Vec3& a, const Vec3& b) const override {
    const double da = signed_distance(a), db = signed_distance(b);
    if (da < 0 || db >= 0) return std::nullopt;  // starts inside, or ends outside
    const double s = da / (da - db);
    return SurfacePoint{a + s * (b - a), n_};
  }

 private:
  Vec3 p0_, n_;
};

/// First s in [0, 1] at which a + s·d enters the round body |P(a + s·d − c)| = R, where P
/// projects on the directions the body is round in (all three for a ball, the plane normal to
/// the axis for a rod). The root of the quadratic with the smaller s is the entry; tangent
/// segments do not enter.
std::optional<double> entry_parameter(const Vec3& a_rel, const Vec3& d, double R) {
  const double A = d.squaredNorm(), B = 2 * d.dot(a_rel), C = a_rel.squaredNorm() - R * R;
  if (C < 0 || !(A > 0)) return std::nullopt;  // starts inside, or no motion across the round
  const double disc = B * B - 4 * A * C;
  if (!(disc > 0) || B >= 0) return std::nullopt;  // misses, grazes, or moves away
  // Entry root (−B − √disc)/2A in the cancellation-free form 2C/(−B + √disc).
  const double s = 2 * C / (-B + std::sqrt(disc));
  if (s > 1) return std::nullopt;
  return s;
}

class Sphere final : public RigidSurface {
 public:
  Sphere(const Vec3& center, double radius) : c_(center), r_(radius) {}
  double signed_distance(const Vec3& p) const override { return (p - c_).norm() - r_; }
  SurfacePoint nearest(const Vec3& p) const override {
    const Vec3 d = p - c_;
    const double len = d.norm();
    const Vec3 n = len > 0 ? Vec3(d / len) : Vec3::UnitZ();
    return {c_ + r_ * n, n};
  }
  std::optional<SurfacePoint> intersection(const Vec3& a, const Vec3& b) const override {
    const auto s = entry_parameter(a - c_, b - a, r_);
    if (!s) return std::nullopt;
    const Vec3 x = a + *s * (b - a);
    return SurfacePoint{x, (x - c_).normalized()};
  }

 private:
  Vec3 c_;
  double r_;
};

class Cylinder final : public RigidSurface {
 public:
  Cylinder(const Vec3& point, const Vec3& axis, double radius)
      : p0_(point), a_(axis.normalized()), r_(radius) {}
  double signed_distance(const Vec3& p) const override { return radial(p).norm() - r_; }
  SurfacePoint nearest(const Vec3& p) const override {
    const Vec3 d = radial(p);
    const double len = d.norm();
    const Vec3 n = len > 0 ? Vec3(d / len) : any_normal();
    return {p - d + r_ * n, n};
  }
  std::optional<SurfacePoint> intersection(const Vec3& a, const Vec3& b) const override {
    const Vec3 seg = b - a;
    const auto s = entry_parameter(radial(a), seg - seg.dot(a_) * a_, r_);
    if (!s) return std::nullopt;
    const Vec3 x = a + *s * seg;
    return SurfacePoint{x, radial(x).normalized()};
  }

 private:
  /// The part of p − p0 normal to the axis.
  Vec3 radial(const Vec3& p) const {
    const Vec3 d = p - p0_;
    return d - d.dot(a_) * a_;
  }
  Vec3 any_normal() const {
    const Vec3 t = std::abs(a_.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return a_.cross(t).normalized();
  }
  Vec3 p0_, a_;
  double r_;
};

}  // namespace

std::unique_ptr<RigidSurface> make_plane(const Vec3& point, const Vec3& normal) {
  return std::make_unique<Plane>(point, normal);
}
std::unique_ptr<RigidSurface> make_sphere(const Vec3& center, double radius) {
  return std::make_unique<Sphere>(center, radius);
}
std::unique_ptr<RigidSurface> make_cylinder(const Vec3& point, const Vec3& axis, double radius) {
  return std::make_unique<Cylinder>(point, axis, radius);
}

using Kind = SurfaceKey::Kind;

SurfaceDeclaration plane_declaration() {
  return {.name = "plane",
          .noun = "a plane",
          .keys = {{.name = "point",
                    .kind = Kind::vector,
                    .description = "a point of the plane",
                    .example = "[x, y, z]"},
                   {.name = "normal",
                    .kind = Kind::unit_vector,
                    .description = "pointing from the rigid body towards the deformable one",
                    .example = "[x, y, z]"}},
          .make = [](const SurfaceParameters& p) {
            return make_plane(p.vector("point"), p.vector("normal"));
          }};
}

SurfaceDeclaration sphere_declaration() {
  return {.name = "sphere",
          .noun = "a sphere",
          .keys = {{.name = "center",
                    .kind = Kind::vector,
                    .description = "the centre of the rigid ball",
                    .example = "[x, y, z]"},
                   {.name = "radius",
                    .kind = Kind::positive,
                    .description = "the radius of the rigid ball",
                    .example = "r"}},
          .make = [](const SurfaceParameters& p) {
            return make_sphere(p.vector("center"), p.number("radius"));
          }};
}

SurfaceDeclaration cylinder_declaration() {
  return {.name = "cylinder",
          .noun = "a cylinder",
          .keys = {{.name = "point",
                    .kind = Kind::vector,
                    .description = "a point of the cylinder's axis",
                    .example = "[x, y, z]"},
                   {.name = "axis",
                    .kind = Kind::unit_vector,
                    .description = "the direction of the axis",
                    .example = "[x, y, z]"},
                   {.name = "radius",
                    .kind = Kind::positive,
                    .description = "the radius of the rigid cylinder",
                    .example = "r"}},
          .make = [](const SurfaceParameters& p) {
            return make_cylinder(p.vector("point"), p.vector("axis"), p.number("radius"));
          }};
}

}  // namespace hencky
