// read_case: the case file, its top-level keys and the rules that span sections. The sections
// are read in case_*.cpp (case_sections.hpp), on the YAML layer of yaml_source.hpp.
#include "input/case_reader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/suggest.hpp"
#include "input/case_sections.hpp"
#include "input/inp_case.hpp"
#include "input/inp_reader.hpp"
#include "input/yaml_source.hpp"
#include "solve/schemes.hpp"

namespace hencky {

namespace fs = std::filesystem;

namespace case_input {
namespace {

const std::vector<std::string> top_keys = {"title",  "mesh",     "materials",  "temperature",
                                           "heat",   "boundary", "body_force", "contact",
                                           "solver", "output"};

/// Every section's keys, in the order the "is a key of ..." hint lists them.
const std::vector<KeySection>& key_sections() {
  static const std::vector<KeySection> all = [] {
    std::vector<KeySection> s = {{"the top level", &top_keys}};
    for (const auto part : {mesh_material_sections(), plasticity_sections(), load_sections(),
                            contact_sections(), solver_output_sections(), heat_sections()})
      s.insert(s.end(), part.begin(), part.end());
    return s;
  }();
  return all;
}

/// Tabs in the indentation are the most common cause of puzzling YAML syntax errors.
std::string tab_hint(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto indent = line.substr(0, line.find_first_not_of(" \t"));
    if (indent.find('\t') != std::string::npos)
      return " (line " + std::to_string(n) + " is indented with a tab; YAML needs spaces)";
  }
  return {};
}

/// The case file's text; `label` is the file as given, for messages.
std::string read_text(const std::string& label, const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec))
    throw InputError(SourceLocation{label, 0, 0, ""}, "case file not found");
  if (!fs::is_regular_file(file, ec))
    throw InputError(SourceLocation{label, 0, 0, ""}, "expected a case file, found a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(SourceLocation{label, 0, 0, ""}, "cannot open the case file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

YAML::Node parse_yaml(const std::string& label, const std::string& text) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "YAML syntax error: " + e.msg + tab_hint(text));
  } catch (const YAML::Exception& e) {
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "cannot read the YAML: " + e.msg);
  }
}

/// Without a temperature section, every material property must be a constant.
void check_no_tables(const std::vector<MaterialSpec>& materials) {
  for (const auto& m : materials) {
    std::vector<const PropertyTable*> props = {&m.E, &m.nu, &m.alpha};
    if (m.plasticity) {
      const CurveSpec& curve = m.plasticity->curve;
      if (curve.kind == CurveSpec::Kind::table && curve.tables.size() > 1)
        throw InputError(curve.tables[1].where,
                         "curve tables at several temperatures need a 'temperature' "
                         "section (with its 'reference' and 'field')");
      if (curve.kind != CurveSpec::Kind::table) props.push_back(&curve.yield);
      if (curve.kind == CurveSpec::Kind::linear) props.push_back(&curve.hardening);
    }
    for (const PropertyTable* p : props)
      if (!p->is_constant())
        throw InputError(p->where,
                         "a table over temperature needs a 'temperature' section "
                         "(with its 'reference' and 'field')");
  }
}

/// A curve that is flat (or falls) from its yield point on at some temperature: perfect
/// plasticity, a linear hardening ≤ 0, a table of one point or whose first segment does not
/// rise. Its strain form F = ε(σ) does not exist above the yield stress.
bool flat_from_yield(const CurveSpec& curve) {
  switch (curve.kind) {
    case CurveSpec::Kind::perfect:
      return true;
    case CurveSpec::Kind::linear:
      return std::any_of(curve.hardening.value.begin(), curve.hardening.value.end(),
                         [](double h) { return h <= 0; });
    case CurveSpec::Kind::table:
      return std::any_of(curve.tables.begin(), curve.tables.end(), [](const CurveSpec::Table& t) {
        return t.stress.size() < 2 || t.stress[1] <= t.stress[0];
      });
    case CurveSpec::Kind::ramberg_osgood:
      return false;
  }
  return false;
}

/// The schemes that iterate on the strain form of the curve stop at once on a curve that has
/// none above its yield stress, instead of failing the first plastic step after iterating.
void check_strain_form(const Case& c) {
  if (!make_scheme(c.solver)->uses_strain_form())
    return;
  for (const auto& m : c.materials)
    if (m.plasticity && flat_from_yield(m.plasticity->curve))
      throw InputError(
          m.plasticity->curve.where,
          fmt::format("scheme '{}'{} iterates on the strain form ε̃ = F(σ̃) of the curve, and "
                      "the curve of material '{}' has none above its yield stress (it is "
                      "flat from there on: perfect plasticity). The schemes that can run it: {}",
                      scheme_name(c.solver.scheme),
                      c.solver.scheme == SchemeKind::variable_stiffness ? " (curve_form: strain)"
                                                                        : "",
                      m.name, schemes_without_strain_form));
}

/// The sections of the top-level map, in the order later ones depend on earlier ones.
void read_sections(const Reader& r, const Map& top, Case& c) {
  c.title = top.has("title") ? r.string(*top.get("title"), "a title") : c.file.stem().string();
  c.mesh = read_mesh(r, top.require(r, "mesh", "the mesh, e.g. mesh: {file: part.msh}"));
  c.materials =
      read_materials(r, top.require(r, "materials", "a list of materials with E, nu and alpha"),
                     top.has("temperature"));
  if (auto x = top.get("temperature")) {
    c.temperature = read_temperature(r, *x);
  } else {  // a table over temperature needs a temperature
    check_no_tables(c.materials);
  }
  if (auto x = top.get("boundary")) c.boundary = read_boundary(r, *x);
  if (auto x = top.get("body_force")) c.body_force = r.expression3(*x);
  if (auto x = top.get("contact")) c.contact = read_contact(r, *x);
  c.solver = read_solver(r, top.get("solver"));
  check_strain_form(c);
  if (auto x = top.get("heat")) c.heat = read_heat(r, *x, c.solver.times);
  check_heat(c);
  c.output =
      read_output(r, top.get("output"), c.file.parent_path() / (c.file.stem().string() + ".out"),
                  c.boundary, c.heat);
}

}  // namespace
}  // namespace case_input

// ---------------------------------------------------------------------------------------------

Case read_case(const fs::path& case_file, std::string* text) {
  // fs::absolute throws on an empty path: say what a missing file says.
  if (case_file.empty())
    throw InputError(SourceLocation{}, "case file not found: the path is empty (\"\")");
  // A CalculiX/Abaqus deck is the case itself: its model and history data.
  if (is_inp_file(case_file)) return read_deck(case_file, text).spec;
  std::string read =
      case_input::read_text(case_file.string(), fs::absolute(case_file).lexically_normal());
  Case c = read_case_text(read, case_file);
  if (text) *text = std::move(read);
  return c;
}

Case read_case_text(const std::string& text, const fs::path& case_file) {
  using namespace case_input;
  const std::string label = case_file.string();
  Case c;
  c.file = fs::absolute(case_file).lexically_normal();
  const YAML::Node root = parse_yaml(label, text);

  const Reader r(label, c.file.parent_path(), key_sections());
  if (!root.IsDefined() || root.IsNull())
    throw InputError(SourceLocation{label, 0, 0, ""},
                     "the case file is empty: expected a map with at least the keys 'mesh' and "
                     "'materials'");
  YAML::Mark top_mark = root.Mark();
  if (top_mark.line < 0) top_mark = YAML::Mark();
  const Val top_val{root, "", top_mark};
  if (!root.IsMap())
    r.fail(top_val, "expected a map of keys (" + name_list(top_keys) +
                        ") at the top level, found " + describe(root));

  try {
    const Map top(r, top_val, top_keys);
    read_sections(r, top, c);
  } catch (const YAML::Exception& e) {  // not expected: all access is checked
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "cannot read the YAML: " + e.msg);
  }
  return c;
}

}  // namespace hencky
