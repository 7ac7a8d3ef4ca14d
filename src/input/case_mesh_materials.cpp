// The mesh and materials sections: the mesh file, the materials with their regions, elastic
// constants and thermal expansion, and property tables over temperature.
#include <cmath>
#include <map>
#include <system_error>

#include "input/case_sections.hpp"
#include "material/elastic.hpp"
#include "material/hardening.hpp"

namespace hencky::case_input {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> mesh_keys = {"file", "order", "scale", "split", "regions"};
const std::vector<std::string> label_region_keys = {"name", "nodes", "elements", "faces"};
const std::vector<std::string> material_keys = {"name",         "regions", "E",
                                                "nu",           "alpha",   "plasticity",
                                                "conductivity", "density", "specific_heat"};
const std::vector<std::string> table_keys = {"temperature", "value"};

const KeySection mesh_material_key_sections[] = {
    {"mesh", &mesh_keys},
    {"mesh.regions[i]", &label_region_keys},
    {"materials[i]", &material_keys},
};

}  // namespace

std::span<const KeySection> mesh_material_sections() {
  return mesh_material_key_sections;
}

// ---------------------------------------------------------------------------------------------
// Mesh

namespace {

/// mesh.regions: regions named by the mesh's node and element labels.
std::vector<LabelRegionSpec> read_label_regions(const Reader& r, const Val& x) {
  std::vector<LabelRegionSpec> regions;
  for (const auto& item : r.entries(x, "a list of regions named by labels")) {
    Map m(r, item, label_region_keys,
          "a region {name: tip, nodes: [labels]} (or elements: [labels], or faces: [[element, "
          "face], ...])");
    LabelRegionSpec g;
    g.where = r.at(item);
    g.name = r.string(m.require(r, "name", "the region's name, as conditions name it"));
    for (const auto& other : regions)
      if (other.name == g.name) r.fail(*m.get("name"), "region '" + g.name + "' is named twice");
    const int lists = m.has("nodes") + m.has("elements") + m.has("faces");
    if (lists != 1)
      r.fail(item, "a region names exactly one of nodes, elements or faces, found " +
                       std::to_string(lists));
    auto labels = [&](const Val& v, std::vector<long>& out) {
      for (const auto& e : r.list(v, "a list of labels [1, 2, ...]")) {
        const long label = r.integer(e);
        if (label < 1) r.fail(e, "a label is a whole number >= 1, found " + std::to_string(label));
        out.push_back(label);
        g.item_where.push_back(r.at(e));
      }
    };
    if (auto v = m.get("nodes")) labels(*v, g.nodes);
    if (auto v = m.get("elements")) labels(*v, g.elements);
    if (auto v = m.get("faces"))
      for (const auto& e : r.list(*v, "a list of faces [[element, face], ...]")) {
        const auto pair = r.list(e, "a face [element label, face number 1 .. 6]");
        if (pair.size() != 2) r.fail(e, "a face is [element label, face number 1 .. 6]");
        const long label = r.integer(pair[0]), face = r.integer(pair[1]);
        if (label < 1) r.fail(pair[0], "an element label is a whole number >= 1");
        if (face < 1 || face > 6) r.fail(pair[1], "a face number is 1 .. 6 (S1 .. S6)");
        g.faces.emplace_back(label, static_cast<int>(face));
        g.item_where.push_back(r.at(e));
      }
    if (g.nodes.empty() && g.elements.empty() && g.faces.empty())
      r.fail(item, "region '" + g.name + "' names no label");
    regions.push_back(std::move(g));
  }
  return regions;
}

}  // namespace

MeshSpec read_mesh(const Reader& r, const Val& v) {
  Map m(r, v, mesh_keys, "a map like {file: part.msh}");
  MeshSpec mesh;
  if (auto g = m.get("regions")) {
    if (auto s = m.get("split"); s && r.choice(*s, {"true", "false"}, "split") == "true")
      r.fail(*g, "regions named by labels go with a whole mesh, not a split one");
    mesh.regions = read_label_regions(r, *g);
  }
  const Val file = m.require(r, "file", "the mesh, e.g. file: part.msh (or .geo, or .inp)");
  mesh.where = r.at(file);
  const std::string name = r.string(file, "a file name");
  mesh.file = r.resolve(name);
  const std::string ext = lower(mesh.file.extension().string());
  if (ext != ".msh" && ext != ".geo" && ext != ".inp")
    r.fail(file,
           "expected a Gmsh mesh (.msh), a Gmsh geometry (.geo) or an Abaqus/CalculiX "
           "deck (.inp), found '" +
               name + "'");
  std::error_code ec;
  if (auto s = m.get("split"); s && r.choice(*s, {"true", "false"}, "split") == "true") {
    // The files Gmsh writes for `gmsh ... -part N -part_split -o cyl.msh`: cyl_1.msh ..
    // cyl_N.msh, one per rank (docs/parallel.md).
    if (ext != ".msh")
      r.fail(*s,
             "a split mesh is a set of .msh files, named after file: (e.g. file: cyl.msh "
             "for cyl_1.msh, cyl_2.msh, ...)");
    if (m.has("order"))
      r.fail(*m.get("order"),
             "the files of a split mesh are read as they are: convert the "
             "order before Gmsh splits the mesh (gmsh -order 2 ...)");
    mesh.split = true;
    while (fs::is_regular_file(piece_file(mesh, mesh.pieces), ec)) ++mesh.pieces;
    if (mesh.pieces == 0)
      r.fail(*s, "split mesh: " + piece_file(mesh, 0).string() +
                     " not found (the files of `gmsh -part N -part_split -o " + name +
                     "` are named " + piece_file(mesh, 0).filename().string() + " .. " +
                     mesh.file.stem().string() + "_N.msh, beside " + name + ")");
    if (auto sc = m.get("scale")) mesh.scale = r.positive(*sc);
    return mesh;
  }
  if (!fs::exists(mesh.file, ec))
    r.fail(file, "mesh file not found: " + mesh.file.string() +
                     " (relative paths are taken from the case file's folder)");
  if (!fs::is_regular_file(mesh.file, ec))
    r.fail(file, "expected a mesh file, found a directory or special file: " + mesh.file.string());
  if (auto o = m.get("order")) {
    const long order = r.integer(*o);
    if (order != 1 && order != 2) r.fail(*o, "expected 1 or 2, found " + std::to_string(order));
    if (ext == ".inp")
      r.fail(*o,
             "an .inp deck is read with the elements it has: mesh.order converts Gmsh meshes "
             "only (write the deck with C3D10 or C3D20 elements for quadratic ones)");
    mesh.order = static_cast<int>(order);
  }
  if (auto s = m.get("scale")) mesh.scale = r.positive(*s);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Property tables

namespace {

void check_property(const Reader& r, const Val& v, Property p, const std::string& what, double x) {
  switch (p) {
    case Property::E:
      if (!(x > 0)) r.fail(v, what + " must be > 0, found " + num(x));
      break;
    case Property::nu:
      if (!(x > -1.0 && x < 0.5))
        r.fail(v, what +
                      " must satisfy -1 < nu < 0.5 (0.5 is incompressible, which this "
                      "displacement formulation cannot solve), found " +
                      num(x));
      break;
    case Property::yield:
    case Property::positive:
      if (!(x > 0)) r.fail(v, what + " must be > 0, found " + num(x));
      break;
    case Property::alpha:
    case Property::any:        // a point law's field: the law checks it (LawDeclaration::make)
    case Property::hardening:  // may be negative (softening); > -3G is checked with E and nu
      break;
  }
}

}  // namespace

PropertyTable read_property(const Reader& r, const Val& v, const std::string& name, Property p) {
  PropertyTable t;
  t.where = r.at(v);
  if (v.node.IsScalar()) {
    t.value = {r.material_number(v)};
    check_property(r, v, p, name, t.value[0]);
    return t;
  }
  if (!v.node.IsMap())
    r.fail(v, "expected a number or a table {temperature: [...], value: [...]}, found " +
                  describe(v.node));
  Map m(r, v, table_keys);
  const Val temp = m.require(r, "temperature", "the table's temperatures, e.g. [20, 500]");
  const Val val = m.require(r, "value", "the values at those temperatures");
  const auto ts = r.list(temp, "a list of temperatures [T1, T2, ...]");
  const auto vs = r.list(val, "a list of values [v1, v2, ...]");
  if (ts.empty()) r.fail(temp, "expected at least one temperature, found an empty list");
  for (std::size_t i = 0; i < ts.size(); ++i) {
    t.temperature.push_back(r.number(ts[i]));
    if (i > 0 && !(t.temperature[i] > t.temperature[i - 1]))
      r.fail(ts[i], "temperatures must be strictly increasing, found " + num(t.temperature[i]) +
                        " after " + num(t.temperature[i - 1]));
  }
  if (vs.size() != ts.size())
    r.fail(val, "expected " + std::to_string(ts.size()) + " values (one per temperature), found " +
                    std::to_string(vs.size()));
  for (std::size_t i = 0; i < vs.size(); ++i) {
    t.value.push_back(r.material_number(vs[i]));
    check_property(r, vs[i], p, name, t.value[i]);
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Materials

namespace {

/// E and nu whose stiffness or compliance leaves the range of floating point (E = 1e308 with
/// nu = 0.3 has a finite E but an infinite E/(1 − 2nu)): checked at every temperature of
/// their tables, where the extremes of these monotone functions of E and nu lie.
void check_elastic_range(const MaterialSpec& mat) {
  std::vector<double> ts = {0.0};
  for (const PropertyTable* p : {&mat.E, &mat.nu})
    ts.insert(ts.end(), p->temperature.begin(), p->temperature.end());
  for (double T : ts) {
    const ElasticConstants k{mat.E(T), mat.nu(T), 0.0};
    const std::pair<const char*, double> parts[] = {
        {"the shear modulus G = E/(2(1 + nu))", k.shear_modulus()},
        {"the Lame constant lambda = E nu/((1 + nu)(1 - 2nu))", k.lame_lambda()},
        {"the bulk stiffness E/(1 - 2nu)", k.E / (1 - 2 * k.nu)},
        {"the compliance 2(1 + nu)/E", 2 * (1 + k.nu) / k.E}};
    for (const auto& [what, value] : parts)
      if (!std::isfinite(value))
        throw InputError(
            mat.E.where,
            "E = " + num(k.E) + " with nu = " + num(k.nu) +
                (mat.E.is_constant() && mat.nu.is_constant() ? std::string()
                                                             : " (at temperature " + num(T) + ")") +
                " gives " + what + " = " + num(value) +
                ", beyond the range of floating point; choose units that keep the "
                "material's numbers moderate (e.g. MPa and mm)");
  }
}

/// The material's law: E, nu, alpha and the plasticity, each checked as far as the case alone
/// allows (the mesh's temperatures are checked later).
void read_material_law(const Reader& r, const Map& m, bool has_temperature, MaterialSpec& mat) {
  mat.E = read_property(r, m.require(r, "E", "Young's modulus in Pa, e.g. E: 2.1e11"), "E",
                        Property::E);
  mat.nu =
      read_property(r, m.require(r, "nu", "Poisson's ratio, e.g. nu: 0.3"), "nu", Property::nu);
  check_elastic_range(mat);
  if (auto a = m.get("alpha")) {
    mat.alpha = read_property(r, *a, "alpha", Property::alpha);
  } else if (has_temperature) {
    m.require(r, "alpha",
              "the thermal expansion coefficient in 1/K, e.g. alpha: 1.2e-5; "
              "it is required because the case has a temperature section");
  } else {
    mat.alpha.value = {0.0};
    mat.alpha.where = mat.where;
  }
  // Heat conduction: whether the case needs them is checked with its heat section.
  for (auto [key, property] :
       {std::pair{"conductivity", &mat.conductivity}, std::pair{"density", &mat.density},
        std::pair{"specific_heat", &mat.specific_heat}}) {
    if (auto x = m.get(key))
      *property = read_property(r, *x, key, Property::positive);
    else
      property->where = SourceLocation{r.label(), mat.where.line, mat.where.column,
                                       child_path(mat.where.key, key)};
  }
  if (auto pl = m.get("plasticity")) {
    mat.plasticity = read_plasticity(r, *pl, mat);
    // Converting the curve needs E and nu: done here only to report a bad curve now (for
    // `hencky check`); the model builds its own.
    (void)Hardening(*mat.plasticity, mat.E, mat.nu);
  }
}

}  // namespace

std::vector<MaterialSpec> read_materials(const Reader& r, const Val& v, bool has_temperature) {
  const auto items = r.entries(v, "a list of materials");
  if (items.empty()) r.fail(v, "expected at least one material, found an empty list");
  std::vector<MaterialSpec> out;
  std::map<std::string, std::size_t> names;
  std::map<std::string, std::size_t> region_owner;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, material_keys, "a material {name: ..., E: ..., nu: ..., alpha: ...}");
    MaterialSpec mat;
    mat.where = r.at(item);
    if (auto n = m.get("name")) {
      mat.name = r.string(*n);
      if (auto prev = names.find(mat.name); prev != names.end())
        r.fail(*n, "material name '" + mat.name + "' is already used by materials[" +
                       std::to_string(prev->second) + "]");
    } else {
      mat.name = "material" + std::to_string(i);
    }
    names.emplace(mat.name, i);
    if (auto regs = m.get("regions")) {
      for (const Val& rv : r.names(*regs)) {
        const std::string reg = r.string(rv, "a region name");
        if (auto prev = region_owner.find(reg); prev != region_owner.end()) {
          if (prev->second == i) r.fail(rv, "region '" + reg + "' is listed twice");
          r.fail(rv, "region '" + reg + "' is already given to material '" +
                         out[prev->second].name + "' (materials[" + std::to_string(prev->second) +
                         "]); a region has one material");
        }
        mat.regions.push_back(reg);
        mat.region_where.push_back(r.at(rv));
        region_owner.emplace(reg, i);
      }
    } else if (items.size() > 1) {
      r.fail(item, "material '" + mat.name +
                       "' needs 'regions' (the Gmsh physical volumes it "
                       "fills): it may be left out only when there is one material");
    }
    read_material_law(r, m, has_temperature, mat);
    out.push_back(std::move(mat));
  }
  return out;
}

}  // namespace hencky::case_input
