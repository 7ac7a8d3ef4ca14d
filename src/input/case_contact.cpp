// The contact section: rigid surfaces touched by the nodes of a region, their motion and the
// penalty settings. The surface types and their keys are the registered ones
// (contact/surface_type.hpp), read here from their declarations.
#include <cmath>
#include <map>
#include <string_view>
#include <system_error>

#include "contact/surface_type.hpp"
#include "input/case_sections.hpp"

namespace hencky::case_input {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> contact_keys = {"name",   "nodes",     "surface",
                                               "motion", "stiffness", "penetration"};

/// The registered surface types (contact/surface_type.hpp), their names and keys as the
/// reader's sections want them (Map compares a section's table by address: built in place,
/// never copied), and the lists the messages give.
struct SurfaceTables {
  std::vector<std::string> names;              ///< plane, sphere, ...
  std::vector<std::vector<std::string>> keys;  ///< each type's keys
  std::vector<std::string> section_names;      ///< contact[i].surface.<type>
  std::vector<KeySection> sections;
  std::string names_listed;  ///< 'plane', 'sphere', 'cylinder', 'mesh'
  std::string names_or;      ///< plane, sphere, cylinder or mesh
  std::string names_bar;     ///< plane|sphere|cylinder|mesh
  std::string sketches;      ///< {plane: ...}, ... or {mesh: {file: ...}}

  SurfaceTables() {
    const auto& types = surface_types();
    for (const SurfaceDeclaration& type : types) {
      names.push_back(type.name);
      keys.emplace_back();
      for (const SurfaceKey& key : type.keys) keys.back().push_back(key.name);
      section_names.push_back("contact[i].surface." + type.name);
    }
    sections = {{"contact[i]", &contact_keys}, {"contact[i].surface", &names}};
    for (std::size_t i = 0; i < types.size(); ++i)
      sections.push_back({section_names[i].c_str(), &keys[i]});
    for (std::size_t i = 0; i < types.size(); ++i) {
      const bool first = i == 0, last = i + 1 == types.size();
      const std::string comma = first ? "" : last ? " or " : ", ";
      names_listed += (first ? "'" : ", '") + types[i].name + "'";
      names_or += comma + types[i].name;
      names_bar += (first ? "" : "|") + types[i].name;
      // A type with one required key shows it: {mesh: {file: ...}}.
      std::vector<std::string> required;
      for (const SurfaceKey& key : types[i].keys)
        if (!key.fallback) required.push_back(key.name);
      const std::string inner = required.size() == 1 ? "{" + required[0] + ": ...}" : "...";
      sketches += comma + "{" + types[i].name + ": " + inner + "}";
    }
  }
  SurfaceTables(const SurfaceTables&) = delete;
  SurfaceTables& operator=(const SurfaceTables&) = delete;
};

const SurfaceTables& surface_tables() {
  static const SurfaceTables t;
  return t;
}

/// "a sphere {center: [x, y, z], radius: r}"
std::string sketch(const SurfaceDeclaration& type) {
  const bool vowel = std::string_view("aeiou").find(type.name.front()) != std::string_view::npos;
  std::string s = (vowel ? "an " : "a ") + type.name + " {";
  for (std::size_t k = 0; k < type.keys.size(); ++k)
    s += (k ? ", " : "") + type.keys[k].name + ": " + type.keys[k].example;
  return s + "}";
}

/// A unit direction from a list of 3 numbers (not all zero).
Vec3 unit_vector(const Reader& r, const Val& v, const std::string& what) {
  const Vec3 d = r.vec3(v);
  if (!(d.norm() > 0)) r.fail(v, "expected a non-zero " + what + ", found [0, 0, 0]");
  return d.normalized();
}

/// A key's value, read and checked by its kind.
SurfaceValue read_surface_value(const Reader& r, const Val& v, const SurfaceKey& key) {
  switch (key.kind) {
    case SurfaceKey::Kind::vector:
      return r.vec3(v);
    case SurfaceKey::Kind::unit_vector:
      return unit_vector(r, v, key.name);
    case SurfaceKey::Kind::positive:
      return r.positive(v);
    case SurfaceKey::Kind::file: {
      fs::path file = r.resolve(r.string(v, "a file name"));
      std::error_code ec;
      if (!fs::is_regular_file(file, ec))
        r.fail(v, key.file_kind + " '" + file.string() + "' not found");
      return file;
    }
  }
  r.fail(v, "unknown kind of surface key");  // not reached: every kind is handled above
}

/// contact[i].surface: one of the registered surface types, with its keys.
void read_surface(const Reader& r, const Val& surface, SurfaceParameters& s) {
  const SurfaceTables& t = surface_tables();
  s.where = r.at(surface);
  Map sm(r, surface, t.names, "a surface " + t.sketches);
  std::vector<std::size_t> given;
  for (std::size_t i = 0; i < t.names.size(); ++i)
    if (sm.has(t.names[i])) given.push_back(i);
  if (given.empty()) r.fail(surface, "expected one of " + t.names_listed + ", found an empty map");
  const std::string& name = t.names[given[0]];
  if (given.size() > 1) {
    const std::string& second = t.names[given[1]];
    throw InputError(r.at(sm.key_mark(second), sm.get(second)->path),
                     "a contact has one surface, found both '" + name + "' and '" + second +
                         "'; write another contact entry");
  }
  const SurfaceDeclaration& type = surface_types()[given[0]];
  s.type = type.name;
  Map pm(r, *sm.get(name), t.keys[given[0]], sketch(type));
  for (const SurfaceKey& key : type.keys) {
    const std::optional<Val> v =
        key.fallback ? pm.get(key.name) : pm.require(r, key.name, key.description);
    s.values[key.name] = v ? SurfaceParameters::Entry{read_surface_value(r, *v, key), r.at(*v)}
                           : SurfaceParameters::Entry{*key.fallback, SourceLocation{}};
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
  return surface_tables().sections;
}

std::vector<ContactSpec> read_contact(const Reader& r, const Val& v) {
  std::vector<ContactSpec> out;
  std::map<std::string, std::size_t> names;
  const auto items = r.entries(v, "a list of contacts");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, contact_keys,
          "a contact {name: ..., nodes: <region>, surface: {" + surface_tables().names_bar +
              ": ...}}");
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

    const Val surface = m.require(r, "surface", "the rigid surface: " + surface_tables().names_or);
    read_surface(r, surface, c.surface);
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
