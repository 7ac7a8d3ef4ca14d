#pragma once
// The section readers of the case reader (private to src/input): one file per group of
// sections, each with its sections' key tables. read_case (case_reader.cpp) reads the top
// level, calls these and checks the rules that span sections.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "input/yaml_source.hpp"
#include "spec/case.hpp"

namespace hencky::case_input {

// ---------------------------------------------------------------------------------------------
// Keys of every map in the case file, by section, in the order the "is a key of ..." hint lists
// them. Later versions' keys are known (never "unknown key").

std::span<const KeySection> mesh_material_sections();  // case_mesh_materials.cpp
std::span<const KeySection> plasticity_sections();     // case_plasticity.cpp
std::span<const KeySection> load_sections();           // case_loads.cpp
std::span<const KeySection> contact_sections();        // case_contact.cpp
std::span<const KeySection> solver_output_sections();  // case_solver_output.cpp
std::span<const KeySection> heat_sections();           // case_heat.cpp

// ---------------------------------------------------------------------------------------------
// Mesh and materials (case_mesh_materials.cpp)

MeshSpec read_mesh(const Reader& r, const Val& v);
std::vector<MaterialSpec> read_materials(const Reader& r, const Val& v, bool has_temperature);

/// Which property a number or table is, for its range check.
enum class Property { E, nu, alpha, yield, hardening, positive, any };

/// A number or a table {temperature: [...], value: [...]}; `name` is used in messages.
PropertyTable read_property(const Reader& r, const Val& v, const std::string& name, Property p);

// ---------------------------------------------------------------------------------------------
// Plasticity (case_plasticity.cpp): the hardening curve as given; converted and checked with E
// and nu by Hardening.

PlasticitySpec read_plasticity(const Reader& r, const Val& v, const MaterialSpec& mat);

// ---------------------------------------------------------------------------------------------
// Temperature and boundary conditions (case_loads.cpp)

TemperatureSpec read_temperature(const Reader& r, const Val& v);
std::vector<BoundarySpec> read_boundary(const Reader& r, const Val& v);

// ---------------------------------------------------------------------------------------------
// Heat conduction (case_heat.cpp): the heat section, read after the solver section (its steps
// default to the mechanical ones), and the rules it makes for the materials and the
// temperature section.

HeatSpec read_heat(const Reader& r, const Val& v, const StepTimes& mechanical);
/// A heat section needs temperature: {reference: ..., from: heat} and every material's
/// conductivity (and density, specific heat when transient); from: heat needs a heat section.
void check_heat(const Case& c);

// ---------------------------------------------------------------------------------------------
// Contact (case_contact.cpp)

std::vector<ContactSpec> read_contact(const Reader& r, const Val& v);

// ---------------------------------------------------------------------------------------------
// Solver and output (case_solver_output.cpp)

SolverSpec read_solver(const Reader& r, const std::optional<Val>& v);
OutputSpec read_output(const Reader& r, const std::optional<Val>& v,
                       const std::filesystem::path& default_dir,
                       const std::vector<BoundarySpec>& boundary, const HeatSpec& heat);

/// Letters, digits, '_' and '-': probe and contact names become column names.
bool valid_probe_name(const std::string& s);

}  // namespace hencky::case_input
