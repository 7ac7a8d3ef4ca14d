#pragma once
// The translation of a deck's materials, conditions and steps into a Case (input/inp_case.hpp):
// the keywords read as the mesh reader meets them (inp_history.cpp), then the conditions resolved
// per node, degree of freedom and face over the steps and grouped into the case's boundary
// entries (inp_history_case.cpp).
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "input/inp_parser.hpp"
#include "spec/case.hpp"

namespace hencky::inp {

/// One *STEP of the deck: its time span in the deck's total time and its increments.
struct DeckStep {
  /// The procedure: *STATIC; *HEAT TRANSFER (temperatures alone); *COUPLED (or UNCOUPLED)
  /// TEMPERATURE-DISPLACEMENT (temperatures, then the displacements they cause).
  enum class Procedure { none, statik, heat, coupled } procedure = Procedure::none;
  double start = 0, end = 1;  ///< total time at its start and end
  double increment = 1;       ///< the first increment (DIRECT: every increment)
  double max_increment = 0;   ///< a transient heat step's largest increment; 0: the period
  bool direct = false;        ///< DIRECT: fixed increments
  bool steady = true;         ///< a heat or coupled step: STEADY STATE (else transient)
  bool nlgeom = false;
  int line = 0;  ///< the *STEP line
  /// Temperatures solved in time: ccx applies the step's conditions at once (a step
  /// amplitude) instead of ramping them over the step.
  bool transient() const { return procedure != Procedure::statik && !steady; }
};

/// An *AMPLITUDE: a piecewise-linear factor over the step's time (or the total time).
struct Amplitude {
  /// The factor over time, linear between its points and constant beyond its ends: a table
  /// whose `temperature` is the time (PropertyTable's interpolation). No value: named by a
  /// condition, not defined yet.
  PropertyTable factor;
  bool total_time = false;  ///< TIME=TOTAL TIME
  std::string name;         ///< as first written
  int used_line = -1;       ///< where a condition first named it
  int used_step = -1;       ///< the last step whose conditions name it (-1: the model data)
  bool defined() const { return !factor.value.empty(); }
};

/// The value of one condition (a load at a node and direction, a pressure on a face, a
/// prescribed displacement, a temperature) in each step: the value it reaches (ramped from the
/// last step's end), or that value times an amplitude.
struct Course {
  struct InStep {
    bool set = false;    ///< defined in this step (else: 0 for a load, free for a displacement)
    bool given = false;  ///< given by a line of this step (not carried from the last one)
    double value = 0;
    int amplitude = -1;  ///< index into DeckCase::amplitudes_, -1: ramped (the *STATIC default)
    int line = 0;        ///< where it was last given
  };
  std::vector<InStep> step;  ///< one per step, filled up to the current one
};

/// The keyword-by-keyword reader of a deck's non-mesh data, and what it makes of it.
class DeckCase final : public History {
 public:
  explicit DeckCase(Case& spec) : spec_(spec) {}
  void keyword(InpReader& reader, const Keyword& k, int at, int first, int end) override;
  void finish(InpReader& reader) override;
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  struct Material {
    MaterialSpec spec;
    int line = 0;
    double expansion_zero = 0;  ///< *EXPANSION, ZERO=
    bool used = false;
    int combined_line = -1;  ///< *PLASTIC, HARDENING=COMBINED: its line; -1: none
    bool cyclic = false;     ///< its *CYCLIC HARDENING came
  };
  using NodeDof = std::pair<long, int>;  ///< node label, direction 0 .. 2

  // Reading (inp_history.cpp).
  std::vector<std::vector<double>> numbers(const InpReader& r, int first, int end) const;
  /// "file:line" of line `at`, for the lists of refusals and warnings.
  std::string place(const InpReader& r, int at) const;
  void refuse(const InpReader& r, int at, const std::string& why);
  void note(const InpReader& r, int at, const std::string& what);
  Material& current_material(const InpReader& r, const Keyword& k, int at);
  void material_keyword(InpReader& r, const Keyword& k, int at, int first, int end);
  void elastic(InpReader& r, const Keyword& k, int at, int first, int end);
  void plastic(InpReader& r, const Keyword& k, int at, int first, int end);
  /// The curve of *PLASTIC or *CYCLIC HARDENING: stress and plastic strain per line, a table
  /// per temperature.
  CurveSpec plastic_curve(InpReader& r, const Keyword& k, int at, int first, int end);
  /// *PLASTIC, HARDENING=COMBINED, DATATYPE=PARAMETERS (Abaqus): Armstrong–Frederick back
  /// stresses on a yield stress.
  void back_stress_parameters(InpReader& r, const Keyword& k, int at, int first, int end,
                              Material& m);
  /// *CYCLIC HARDENING: the isotropic part of HARDENING=COMBINED.
  void cyclic_hardening(InpReader& r, const Keyword& k, int at, int first, int end);
  void section(InpReader& r, const Keyword& k, int at, int first, int end);
  void initial_conditions(InpReader& r, const Keyword& k, int at, int first, int end);
  void amplitude(InpReader& r, const Keyword& k, int at, int first, int end);
  void step(InpReader& r, const Keyword& k, int at);
  void statik(InpReader& r, const Keyword& k, int at, int first, int end);
  /// The amplitude a condition keyword names (-1: none); `op_new` from OP=NEW.
  int condition_options(InpReader& r, const Keyword& k, int at, bool& op_new,
                        const std::vector<std::string>& allowed);
  void boundary(InpReader& r, const Keyword& k, int at, int first, int end);
  void cload(InpReader& r, const Keyword& k, int at, int first, int end);
  void dload(InpReader& r, const Keyword& k, int at, int first, int end);
  void temperature(InpReader& r, const Keyword& k, int at, int first, int end);
  // Heat transfer (inp_history_heat.cpp).
  void heat_procedure(InpReader& r, const Keyword& k, int at, int first, int end);
  void physical_constants(InpReader& r, const Keyword& k, int at);
  /// *FILM, *RADIATE, *DFLUX: conditions on element faces.
  void face_heat(InpReader& r, const Keyword& k, int at, int first, int end);
  /// *CFLUX: a heat flow into each node named.
  void cflux(InpReader& r, const Keyword& k, int at, int first, int end);
  void output_request(InpReader& r, const Keyword& k, int at, int first, int end);
  /// The course of a condition, with a slot for the current step.
  Course::InStep& in_step(Course& c);
  /// OP=NEW at line `at`: the conditions of `courses` the step has not named yet are removed;
  /// `to_zero`: a load, which goes to 0 over the step; else a displacement (released) or a
  /// temperature (back to the initial one).
  template <class Courses>
  void remove_unnamed(Courses& courses, int at, bool to_zero) {
    for (auto& [key, c] : courses) {
      Course::InStep& s = in_step(c);
      if (s.given) continue;
      s = to_zero ? Course::InStep{true, false, 0.0, -1, at} : Course::InStep{};
    }
  }
  int step_index() const { return static_cast<int>(steps_.size()) - 1; }

  // The Case (inp_history_case.cpp).
  /// The value of the course at total time t, as ccx ramps it, as a muparser expression of t.
  std::string expression(const Course& c) const;
  double value_at_end(const Course& c, int s) const;
  std::string amplitude_expression(const Amplitude& a, double start) const;
  void build_materials(InpReader& r);
  void build_steps();
  void build_boundary(InpReader& r);
  void build_loads(InpReader& r);
  void build_temperature(InpReader& r);
  /// The heat section of a deck with heat transfer or coupled steps (inp_history_heat.cpp).
  void build_heat(InpReader& r);
  /// Its boundary entries: the prescribed temperatures, fluxes, films and radiation, each
  /// course's nodes (faces) a region.
  void build_heat_boundary(InpReader& r);
  /// Every material has a conductivity, and for a transient a density and a specific heat.
  void check_heat_materials(InpReader& r, int step_line);
  /// Nodes (faces) by the expressions of their condition, (value, ambient), with the line
  /// the group's first was given on: each group becomes one region.
  template <class Key>
  using Groups = std::map<std::array<std::string, 2>, std::pair<std::vector<Key>, int>>;
  /// The courses that are not 0 throughout, grouped by their expression (defined below: the
  /// loads' faces and the heat conditions share it).
  template <class Key>
  Groups<Key> group_courses(std::map<Key, Course>& courses);
  /// One heat.boundary entry of `kind` per group, its region named STEM-1, STEM-2, ...
  template <class Key>
  void add_heat_entries(InpReader& r, HeatBoundarySpec::Kind kind, const char* stem,
                        const Groups<Key>& groups);
  bool has_heat() const;

  Case& spec_;
  std::vector<std::string> warnings_;
  std::vector<std::string> refusals_;  ///< "file:line: *KEYWORD: why"
  int first_refusal_ = -1;
  std::vector<Material> materials_;
  /// The *SOLID SECTION lines (ELSET, MATERIAL), bound to the materials at the end: ccx takes a
  /// material defined after the section that names it.
  struct Section {
    std::string elset, material;
    int line = 0;
  };
  std::vector<Section> sections_;
  void bind_sections(InpReader& r);
  int material_ = -1;                        ///< the *MATERIAL the property keywords belong to
  std::map<std::string, int> amplitude_of_;  ///< by upper-case name
  std::vector<Amplitude> amplitudes_;
  std::vector<DeckStep> steps_;
  bool in_step_ = false, step_has_procedure_ = false;
  /// Conditions per node and direction (displacements, nodal loads), per face (pressures) and
  /// per node (temperatures); a condition of the model data belongs to the first step.
  std::map<NodeDof, Course> displacement_, cload_;
  std::map<ElementFace, Course> pressure_;
  std::map<long, Course> temperature_;
  /// Heat transfer: prescribed temperatures (*BOUNDARY on degree of freedom 11) and heat flows
  /// (*CFLUX) per node;
  /// per face, a flux (*DFLUX), a film (*FILM: h and the sink temperature) and radiation
  /// (*RADIATE: the emissivity and the sink temperature).
  std::map<long, Course> fixed_temperature_, cflux_;
  std::map<ElementFace, Course> flux_;
  std::map<ElementFace, std::array<Course, 2>> film_, radiate_;
  std::optional<double> absolute_zero_, stefan_boltzmann_;
  int constants_line_ = -1;
  std::map<long, double> initial_temperature_;
  int initial_line_ = -1;
  struct Gravity {
    std::array<double, 3> g{0, 0, 0};
    int line = 0;
    int step = 0;
  };
  std::vector<Gravity> gravity_;
  std::map<std::string, int> notes_;  ///< output requests and the like: warned once each
  /// The output requests of each step (inp_history_output.cpp).
  std::vector<std::vector<DeckRequest>> requests_;
  /// The output frequency of the prints and of the files in each step (ccx keeps one of each).
  std::vector<std::array<int, 2>> frequency_;
  void build_requests();
};

template <class Key>
DeckCase::Groups<Key> DeckCase::group_courses(std::map<Key, Course>& courses) {
  Groups<Key> groups;
  for (auto& [key, c] : courses) {
    in_step(c);
    const std::string e = expression(c);
    if (e == "0") continue;
    auto& g = groups[{e, ""}];
    if (g.first.empty()) g.second = c.step.back().line;
    g.first.push_back(key);
  }
  return groups;
}

}  // namespace hencky::inp
