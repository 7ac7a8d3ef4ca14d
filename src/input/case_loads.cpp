// The loads: the temperature section (reference and field) and the boundary conditions.
#include <map>
#include <utility>

#include "input/case_sections.hpp"
#include "input/temperature_csv.hpp"

namespace hencky::case_input {

namespace {

const std::vector<std::string> temperature_keys = {"reference", "field", "from", "interpolation"};
const std::vector<std::string> temperature_sources = {"heat"};
const std::vector<std::string> field_file_keys = {"file"};
const std::vector<std::string> boundary_keys = {"region",   "displacement", "pressure",
                                                "traction", "force",        "nodal_force"};
const std::vector<std::string> conditions = {"displacement", "pressure", "traction", "force",
                                             "nodal_force"};
const std::vector<std::string> xyz_keys = {"x", "y", "z"};

const KeySection load_key_sections[] = {
    {"temperature", &temperature_keys},
    {"boundary[i]", &boundary_keys},
    {"boundary[i].displacement", &xyz_keys},
};

}  // namespace

std::span<const KeySection> load_sections() {
  return load_key_sections;
}

// ---------------------------------------------------------------------------------------------
// Temperature

TemperatureSpec read_temperature(const Reader& r, const Val& v) {
  Map m(r, v, temperature_keys,
        "a map {reference: ..., field: ...} or {reference: ..., from: heat}");
  TemperatureSpec t;
  t.given = true;
  t.where = r.at(v);
  const Val reference = m.require(
      r, "reference", "the stress-free temperature T_ref; it is never guessed, e.g. reference: 20");
  t.reference = r.number(reference);
  t.reference_where = r.at(reference);
  if (auto i = m.get("interpolation"))
    t.linear_in_quadratic_cells = r.choice(*i, {"element", "linear"}, "interpolation") == "linear";
  if (auto from = m.get("from")) {
    if (m.has("field"))
      throw InputError(r.at(m.key_mark("field"), child_path(v.path, "field")),
                       "give either 'field' or 'from: heat', not both");
    r.choice(*from, temperature_sources, "temperature source");
    t.from_heat = true;
    t.field_where = r.at(*from);
    return t;
  }
  const Val f = m.require(
      r, "field", "the temperature: a number, an expression in x, y, z, t or {file: temps.csv}");
  t.field_where = r.at(f);
  if (f.node.IsMap()) {
    Map fm(r, f, field_file_keys, "{file: temps.csv}");
    const Val file = fm.require(r, "file", "the CSV file with the nodal temperatures");
    t.field_where = r.at(file);
    t.file = read_temperature_csv(r, file);
  } else if (f.node.IsScalar()) {
    t.field = r.expression(f);
  } else {
    r.fail(f, "expected a number, an expression in x, y, z, t or {file: temps.csv}, found " +
                  describe(f.node));
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Boundary conditions

namespace {

using Prescribed = std::map<std::pair<std::string, int>, std::size_t>;  // (region, axis) -> entry

/// The components of boundary[i].displacement; each component of a region is prescribed once.
void read_displacement(const Reader& r, const Val& c, std::size_t i, Prescribed& prescribed,
                       BoundarySpec& b) {
  b.kind = BoundaryKind::displacement;
  Map d(r, c, xyz_keys, "a map of components like {x: 0, z: \"0.001*t\"}");
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    auto comp = d.get(xyz_keys[k]);
    if (!comp) continue;
    any = true;
    b.components[k] = r.expression(*comp);
    const auto key = std::make_pair(b.region, k);
    if (auto prev = prescribed.find(key); prev != prescribed.end())
      r.fail(*comp, "the " + xyz_keys[k] + " displacement of region '" + b.region +
                        "' is already prescribed by boundary[" + std::to_string(prev->second) +
                        "]");
    prescribed.emplace(key, i);
  }
  if (!any) r.fail(c, "expected at least one of x, y, z, found an empty map");
}

}  // namespace

std::vector<BoundarySpec> read_boundary(const Reader& r, const Val& v) {
  std::vector<BoundarySpec> out;
  Prescribed prescribed;
  const auto items = r.entries(v, "a list of conditions");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, boundary_keys,
          "a condition {region: ..., displacement|pressure|traction|force|nodal_force: ...}");
    BoundarySpec b;
    const Val region = m.require(r, "region", "the Gmsh physical group the condition acts on");
    if (region.node.IsSequence())
      r.fail(region, "expected one region name, found a list; write one entry per region");
    b.region = r.string(region, "a region name");
    b.where = r.at(region);

    std::vector<std::string> given;
    for (const auto& c : conditions)
      if (m.has(c)) given.push_back(c);
    if (given.empty())
      r.fail(item, "boundary entry for region '" + b.region +
                       "' has no condition: expected one of 'displacement', 'pressure', "
                       "'traction', 'force', 'nodal_force'");
    if (given.size() > 1) {
      const Val second = *m.get(given[1]);
      throw InputError(r.at(m.key_mark(given[1]), second.path),
                       "a boundary entry has one condition, found both '" + given[0] + "' and '" +
                           given[1] + "'; write another entry for the same region");
    }
    const Val c = *m.get(given[0]);
    if (given[0] == "displacement") {
      read_displacement(r, c, i, prescribed, b);
    } else if (given[0] == "pressure") {
      b.kind = BoundaryKind::pressure;
      b.pressure = r.expression(c);
    } else {
      b.kind = given[0] == "traction" ? BoundaryKind::traction
               : given[0] == "force"    ? BoundaryKind::force
                                        : BoundaryKind::nodal_force;
      auto e = r.expression3(c);
      for (int k = 0; k < 3; ++k) b.components[k] = std::move(e[k]);
    }
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace hencky::case_input
