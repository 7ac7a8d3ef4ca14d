// The contact section: rigid surfaces (plane, sphere, cylinder, STL mesh) touched by the nodes
// of a region, their motion and the penalty settings.
#include <cmath>
#include <map>
#include <system_error>

#include "input/case_sections.hpp"

namespace hencky::case_input {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> contact_keys = {"name",   "nodes",     "surface",
                                               "motion", "stiffness", "penetration"};
const std::vector<std::string> surface_kinds = {"plane", "sphere", "cylinder", "mesh"};
const std::vector<std::string> plane_keys = {"point", "normal"};
const std::vector<std::string> sphere_keys = {"center", "radius"};
const std::vector<std::string> cylinder_keys = {"point", "axis", "radius"};
const std::vector<std::string> stl_keys = {"file", "scale"};

const KeySection sections[] = {
    {"contact[i]", &contact_keys},
    {"contact[i].surface", &surface_kinds},
    {"contact[i].surface.plane", &plane_keys},
    {"contact[i].surface.sphere", &sphere_keys},
    {"contact[i].surface.cylinder", &cylinder_keys},
    {"contact[i].surface.mesh", &stl_keys},
};

/// A unit direction from a list of 3 numbers (not all zero).
Vec3 unit_vector(const Reader& r, const Val& v, const char* what) {
  const Vec3 d = r.vec3(v);
  if (!(d.norm() > 0)) r.fail(v, std::string("expected a non-zero ") + what + ", found [0, 0, 0]");
  return d.normalized();
}

/// contact[i].surface: one of plane, sphere, cylinder, mesh.
void read_surface(const Reader& r, const Val& surface, ContactSpec& c) {
  c.surface_where = r.at(surface);
  Map sm(r, surface, surface_kinds,
         "a surface {plane: ...}, {sphere: ...}, {cylinder: ...} or {mesh: {file: ...}}");
  std::vector<std::string> given;
  for (const auto& k : surface_kinds)
    if (sm.has(k)) given.push_back(k);
  if (given.empty())
    r.fail(surface, "expected one of 'plane', 'sphere', 'cylinder', 'mesh', found an empty map");
  if (given.size() > 1)
    throw InputError(r.at(sm.key_mark(given[1]), sm.get(given[1])->path),
                     "a contact has one surface, found both '" + given[0] + "' and '" + given[1] +
                         "'; write another contact entry");
  const Val g = *sm.get(given[0]);
  if (given[0] == "plane") {
    c.shape = ContactSpec::Shape::plane;
    Map pm(r, g, plane_keys, "a plane {point: [x, y, z], normal: [x, y, z]}");
    c.point = r.vec3(pm.require(r, "point", "a point of the plane"));
    c.normal = unit_vector(
        r, pm.require(r, "normal", "pointing from the rigid body towards the deformable one"),
        "normal");
  } else if (given[0] == "sphere") {
    c.shape = ContactSpec::Shape::sphere;
    Map pm(r, g, sphere_keys, "a sphere {center: [x, y, z], radius: r}");
    c.center = r.vec3(pm.require(r, "center", "the centre of the rigid ball"));
    c.radius = r.positive(pm.require(r, "radius", "the radius of the rigid ball"));
  } else if (given[0] == "cylinder") {
    c.shape = ContactSpec::Shape::cylinder;
    Map pm(r, g, cylinder_keys, "a cylinder {point: [x, y, z], axis: [x, y, z], radius: r}");
    c.point = r.vec3(pm.require(r, "point", "a point of the cylinder's axis"));
    c.axis = unit_vector(r, pm.require(r, "axis", "the direction of the axis"), "axis");
    c.radius = r.positive(pm.require(r, "radius", "the radius of the rigid cylinder"));
  } else {
    c.shape = ContactSpec::Shape::mesh;
    Map pm(r, g, stl_keys, "a mesh {file: body.stl, scale: 1}");
    const Val f = pm.require(r, "file", "a closed triangulated body in STL (ASCII or binary)");
    c.file = r.resolve(r.string(f, "a file name"));
    std::error_code ec;
    if (!fs::is_regular_file(c.file, ec)) r.fail(f, "STL file '" + c.file.string() + "' not found");
    if (auto x = pm.get("scale")) c.scale = r.positive(*x);
  }
}

/// The penalty: stiffness (a number or auto) and the allowed penetration.
void read_penalty(const Reader& r, const Map& m, ContactSpec& c) {
  if (auto x = m.get("stiffness"))
    c.stiffness = r.positive_or_auto(*x, "a penalty stiffness > 0 (force per length, per node)");
  if (auto x = m.get("penetration")) {
    c.penetration = r.positive(*x);
    if (c.penetration >= 1)
      r.fail(*x, "expected a fraction of the element size < 1, found " + num(c.penetration));
  }
}

}  // namespace

std::span<const KeySection> contact_sections() {
  return sections;
}

std::vector<ContactSpec> read_contact(const Reader& r, const Val& v) {
  std::vector<ContactSpec> out;
  std::map<std::string, std::size_t> names;
  const auto items = r.entries(v, "a list of contacts");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, contact_keys,
          "a contact {name: ..., nodes: <region>, surface: {plane|sphere|cylinder|mesh: ...}}");
    ContactSpec c;
    c.where = r.at(item);
    c.name = "contact" + std::to_string(i);
    if (auto x = m.get("name")) {
      c.name = r.string(*x);
      if (!valid_probe_name(c.name))
        r.fail(*x,
               "contact names may use letters, digits, '_' and '-' only (they become column "
               "names), found '" +
                   c.name + "'");
    }
    if (auto prev = names.find(c.name); prev != names.end())
      r.fail(m.has("name") ? *m.get("name") : item, "contact name '" + c.name +
                                                        "' is already used by contact[" +
                                                        std::to_string(prev->second) + "]");
    names.emplace(c.name, i);
    const Val nodes = m.require(r, "nodes",
                                "the surface region of the body whose nodes may touch the rigid "
                                "surface");
    if (nodes.node.IsSequence())
      r.fail(nodes, "expected one region name, found a list; write one contact per region");
    c.nodes = r.string(nodes, "a region name");
    c.nodes_where = r.at(nodes);

    const Val surface =
        m.require(r, "surface", "the rigid surface: plane, sphere, cylinder or mesh");
    read_surface(r, surface, c);
    if (auto x = m.get("motion")) {
      auto items3 = r.list3(*x, "numbers or expressions in t");
      for (int k = 0; k < 3; ++k) {
        Expression e = r.expression(items3[k]);
        if (e.depends_on_position())
          r.fail(items3[k], "the motion is a rigid translation: it may depend on t only, found '" +
                                e.text() + "'");
        c.motion[k] = std::move(e);
      }
    }
    read_penalty(r, m, c);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace hencky::case_input
