#include "contact/surface_type.hpp"

#include "core/invariant.hpp"

namespace hencky {

const std::vector<SurfaceDeclaration>& surface_types() {
  // The registry: one line per type.
  static const std::vector<SurfaceDeclaration> types = {
      plane_declaration(),
      sphere_declaration(),
      cylinder_declaration(),
      stl_mesh_declaration(),
  };
  return types;
}

const SurfaceDeclaration& surface_type(const std::string& name) {
  for (const SurfaceDeclaration& d : surface_types())
    if (d.name == name) return d;
  HENCKY_VERIFY(false, "no surface type '" + name + "' is registered");
  return surface_types().front();  // not reached
}

SurfaceDescription describe_keys(const SurfaceParameters& p) {
  SurfaceDescription out = {{"shape", p.type}};
  for (const SurfaceKey& key : surface_type(p.type).keys) {
    const SurfaceValue& v = p.values.at(key.name).value;
    if (const auto* path = std::get_if<std::filesystem::path>(&v))
      out.emplace_back(key.name, path->string());
    else if (const auto* x = std::get_if<Vec3>(&v))
      out.emplace_back(key.name, *x);
    else
      out.emplace_back(key.name, std::get<double>(v));
  }
  return out;
}

}  // namespace hencky
