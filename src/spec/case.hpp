#pragma once
// The case (docs/case-reference.md and the contract CASE_FORMAT.md) as plain typed structs:
// what every layer above reads. input/case_reader.hpp reads a case file into them and checks
// everything that can be checked without the mesh; region names, probe points and
// temperature-file node tags are checked against the mesh later (use core/suggest.hpp for the
// messages and the *_where locations below).
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/error.hpp"
#include "core/expression.hpp"
#include "core/types.hpp"

namespace hencky {

/// Whether the temperatures T_min .. T_max of the integration points reach outside lo .. hi by
/// more than round-off: a point temperature interpolated from nodal values equal to an end
/// (Σ N_a = 1 to round-off) may fall an ulp outside it without leaving the range.
/// A slack of 1e-4 of the table's span: a quadratic element's temperatures under- and
/// overshoot its nodes' between them (a weld plate's 20 °C edge read 19.99 at a point, against a
/// table from 20 to 1500), and the end value used there is the table's to that fraction.
inline bool leaves_range(double T_min, double T_max, double lo, double hi) {
  const double slack = 1e-4 * (hi - lo);
  return T_min < lo - slack || T_max > hi + slack;
}

/// A material property (E, nu or alpha): a constant, or a table over temperature.
struct PropertyTable {
  /// Table temperatures, strictly increasing; empty when the property was given as a number.
  std::vector<double> temperature;
  /// Values; size 1 for a constant, else temperature.size().
  std::vector<double> value;
  SourceLocation where;  ///< where the property is given (key e.g. "materials[0].E")

  /// Value at temperature T, interpolated linearly. Outside the table the end value is used
  /// and *outside (when given) is set to true; otherwise it is set to false.
  double operator()(double T, bool* outside = nullptr) const;
  /// dvalue/dT at T: the slope of the table's segment that holds T (the upper one at a table
  /// temperature), 0 for a constant and outside the table.
  double slope(double T) const;
  bool is_constant() const { return value.size() == 1; }
  /// A table that the temperatures T_min .. T_max leave (leaves_range); never a constant (nor
  /// a property that was not given).
  bool left_by(double T_min, double T_max) const {
    return temperature.size() >= 2 &&
           leaves_range(T_min, T_max, temperature.front(), temperature.back());
  }
};

/// A hardening curve as given in the case file (materials[i].plasticity). Conversion to the
/// formulation's form and every check that needs E and ν happen in material/hardening.hpp.
struct CurveSpec {
  enum class Kind { table, perfect, linear, ramberg_osgood };
  /// How a table's (strain, stress) pairs are read: uniaxial = stress vs total uniaxial strain
  /// (first point on the elastic line σ = E·ε); plastic = stress vs equivalent plastic strain
  /// (first strain 0); intensity = σ̃ vs ε̃^{e+p} of (1.18) (first point on σ̃ = 3G·ε̃).
  enum class Form { uniaxial, plastic, intensity };
  struct Table {
    double temperature = 0;
    std::vector<double> strain, stress;       ///< same length >= 1; strain strictly increasing
    SourceLocation where;                     ///< the entry curve.table[j]
    std::vector<SourceLocation> point_where;  ///< location of each strain value
  };
  Kind kind = Kind::table;
  Form form = Form::uniaxial;
  std::vector<Table> tables;  ///< kind == table: one per temperature, temperatures increasing
  PropertyTable yield;        ///< perfect, linear, ramberg_osgood: initial yield stress (> 0)
  PropertyTable hardening;    ///< linear: plastic modulus dσ/dε^p (may be negative: softening)
  double ro_E = 0, ro_alpha = 0, ro_n = 0;  ///< ramberg_osgood: ε = σ/E + α(σ_y/E)(σ/σ_y)^n
  SourceLocation where;  ///< the curve (or perfect / linear / ramberg_osgood) entry
};

/// The keys a point law reads under `plasticity:` besides the isotropic curve, as the law
/// declares them (material/point_law.hpp): per key, a list of groups of named fields, each a
/// number or a temperature table. `law` names the registered law those keys selected; empty for
/// von Mises with the isotropic curve alone.
struct LawParameters {
  using Group = std::map<std::string, PropertyTable>;
  std::string law;
  std::map<std::string, std::vector<Group>> keys;
  SourceLocation where;  ///< the key that selected the law
};

struct PlasticitySpec {
  CurveSpec curve;
  LawParameters law;  ///< a point law's own keys (kinematic hardening, ...)
  /// elastic: unloading and reloading below the largest intensity reached follow a line of
  /// slope 3G (the report's elastic unloading); curve: unloading follows the curve back
  /// (deformation theory, nonlinear elastic).
  enum class Unloading { elastic, curve } unloading = Unloading::elastic;
  SourceLocation where;  ///< the plasticity entry
};

struct MaterialSpec {
  std::string name;                          ///< unique; default "material<i>"
  std::vector<std::string> regions;          ///< Gmsh physical volume names; empty: the whole
                                             ///< mesh (only allowed with exactly one material)
  std::vector<SourceLocation> region_where;  ///< location of each region name
  PropertyTable E, nu, alpha;                ///< alpha is 0 when not given (only allowed
                                             ///< without a temperature section)
  /// Heat conduction (a `heat` section): k in W/(m·K), ρ in kg/m³, c in J/(kg·K). Not given:
  /// no value (PropertyTable::value empty); conductivity is required by every heat analysis,
  /// density and specific_heat by a transient one.
  PropertyTable conductivity, density, specific_heat;
  std::optional<PlasticitySpec> plasticity;  ///< none: elastic
  SourceLocation where;                      ///< the entry materials[i]
};

/// Nodal temperatures over time from a CSV file.
struct TemperatureFile {
  std::filesystem::path path;   ///< absolute
  std::vector<double> times;    ///< from the header row, strictly increasing
  std::vector<long> node_tags;  ///< Gmsh node tag of each row, unique, > 0
  std::vector<double> values;   ///< values[row * times.size() + j]: node_tags[row] at times[j]

  /// Temperature of row `row` at time t, linear in time; the end values outside [times].
  double at(std::size_t row, double t) const;
};

struct TemperatureSpec {
  bool given = false;    ///< a temperature section is present
  double reference = 0;  ///< T_ref, the stress-free temperature (required when given)
  /// T(x, y, z, t); exactly one of field / file / from_heat is set
  std::optional<Expression> field;
  std::optional<TemperatureFile> file;  ///< when given
  bool from_heat = false;               ///< `from: heat`: the heat section's solution
  /// `interpolation: linear`: in quadratic cells the integration points' temperatures are as ccx
  /// takes them (ReferenceTable::N_linear_temperature: a 20-node hexahedron's field projected
  /// onto the trilinear functions, a 10-node tetrahedron's corners with the linear functions);
  /// default `element`: the cell's own functions, mid-edge nodes included.
  bool linear_in_quadratic_cells = false;
  SourceLocation where;            ///< the temperature section
  SourceLocation reference_where;  ///< the value of temperature.reference
  SourceLocation field_where;      ///< the value of temperature.field (key temperature.field.file
                                   ///< for a file)
};

/// One condition of heat.boundary: a region's faces (or, for a temperature, its nodes).
struct HeatBoundarySpec {
  enum class Kind { temperature, flux, convection, radiation, nodal_flux };
  std::string region;
  Kind kind = Kind::temperature;
  /// temperature: the prescribed temperature; flux: the heat flux into the body (W/m²);
  /// nodal_flux: the heat flow into each node of the region (W; CalculiX's *CFLUX);
  /// convection: the film coefficient h (W/(m²·K)); radiation: the emissivity (0 .. 1). An
  /// expression of x, y, z, t.
  Expression value;
  Expression ambient;          ///< convection, radiation: the ambient temperature T∞
  SourceLocation where;        ///< location of the region name (key heat.boundary[i].region)
  SourceLocation value_where;  ///< the value's key (e.g. heat.boundary[i].convection.h)
};
const char* to_string(HeatBoundarySpec::Kind kind);

/// The `heat` section: heat conduction on the same mesh, k(T) ∇²T + Q = ρc(T) ∂T/∂t, solved
/// step by step before the mechanical step that needs its temperatures (solve/heat.hpp).
struct HeatSpec {
  bool given = false;
  bool transient = false;  ///< analysis: steady (false, the default) | transient
  /// Initial temperature (transient; the first guess of a steady one), an expression of
  /// x, y, z; not given: temperature.reference.
  std::optional<Expression> initial;
  double theta = 1.0;  ///< θ-method: 1 backward Euler (the default), 1/2 Crank–Nicolson
  Expression source;   ///< volumetric heat source in W/m³, an expression of x, y, z, t, T
  std::vector<HeatBoundarySpec> boundary;
  /// The thermal steps' end times (heat.steps / heat.times); not given: the mechanical ones.
  std::vector<double> times;
  double tolerance = 1e-8;  ///< Newton: relative residual and temperature change
  int max_iterations = 30;
  /// Radiation: the absolute zero in the case's temperature unit (-273.15 for °C, 0 for K),
  /// required with radiation, and σ in W/(m²·K⁴).
  std::optional<double> absolute_zero;
  double stefan_boltzmann = 5.670374419e-8;
  /// A heat analysis alone (a deck of *HEAT TRANSFER steps, docs/ccx-decks.md): each step is
  /// the heat solution at its time; nothing mechanical is solved (the displacements, stresses
  /// and forces stay zero) and the materials need no elastic constants.
  bool only = false;
  /// A transient's prescribed temperatures hold from t = 0 on: the nodes start at their
  /// prescribed value at t = 0 rather than at `initial` (what ccx does, for a deck); the
  /// default keeps the initial field, which the first step's capacity term then sees.
  bool fixed_from_start = false;
  SourceLocation where;  ///< the heat section
};

/// force: a total force spread over a face region by area; nodal_force: the vector on each node
/// of a region of any dimension (CalculiX's *CLOAD).
enum class BoundaryKind { displacement, pressure, traction, force, nodal_force };
const char* to_string(BoundaryKind kind);

struct BoundarySpec {
  std::string region;
  BoundaryKind kind = BoundaryKind::displacement;
  /// displacement: the prescribed ones of x, y, z; traction / force / nodal_force: all three.
  std::array<std::optional<Expression>, 3> components;
  std::optional<Expression> pressure;  ///< pressure only; acts along -n (into the body)
  SourceLocation where;                ///< location of the region name (key boundary[i].region)
};

struct ProbeSpec {
  std::string name;  ///< unique; letters, digits, '_' and '-'
  Vec3 point = Vec3::Zero();
  SourceLocation where;  ///< location of the point (key output.probes[i].point)
};

/// A frictionless contact of the body's nodes with a rigid surface (report section 3).
/// A value of a rigid surface's key, as its type declares the key (contact/surface_type.hpp):
/// a number, a 3-vector (a unit one already normalized) or a file's absolute path.
using SurfaceValue = std::variant<double, Vec3, std::filesystem::path>;

/// A contact's rigid surface as the case gives it: the registered surface type its key names
/// (plane, sphere, cylinder, mesh: surface_types(), contact/surface_type.cpp) and the values of
/// that type's keys, read and checked as the type declares them; an optional key not given
/// has its default (and no location).
struct SurfaceParameters {
  struct Entry {
    SurfaceValue value;
    SourceLocation where;  ///< the key's value in the case file
  };
  std::string type;                     ///< the type's name, its key under `surface`
  std::map<std::string, Entry> values;  ///< by key
  SourceLocation where;                 ///< the surface, contact[i].surface

  /// The value of a key the type declares of that kind (InternalError otherwise: the type's
  /// `make` asks for a key its declaration does not have).
  double number(const std::string& key) const;
  const Vec3& vector(const std::string& key) const;
  const std::filesystem::path& path(const std::string& key) const;
};

struct ContactSpec {
  std::string name;   ///< unique; letters, digits, '_' and '-' (it names history.csv columns)
  std::string nodes;  ///< surface region (Gmsh physical surface) whose nodes may touch
  SurfaceParameters surface;                        ///< the rigid surface where it starts
  std::array<std::optional<Expression>, 3> motion;  ///< translation over time; none: 0
  std::optional<double> stiffness;  ///< penalty κ per node (force/length); none: auto
  /// Allowed penetration (and gap of a pressed node), relative to the local element size.
  double penetration = 1e-3;
  SourceLocation where;        ///< the entry contact[i]
  SourceLocation nodes_where;  ///< location of the region name
};

/// The most steps a case may have (solver.steps, or the length of solver.times). Each step
/// costs at least a solve, a history row and a log line, and its fields are written every
/// output.every steps: a million steps write 440 MB of history and log even on a 4-element
/// mesh and take hours to weeks on a real one, and more steps than that resolve no load path
/// better (docs/case-reference.md, solver).
inline constexpr long max_steps = 1000000;

/// The end times of the steps: strictly increasing, > 0, at least one, at most max_steps.
/// Equal steps (solver.steps and solver.end) are kept as their rule, not as a list, so that
/// reading and checking a case allocates nothing per step.
class StepTimes {
 public:
  /// One step, to t = 1 (the default).
  StepTimes() = default;
  /// n equal steps over [0, end]: step k = 1 .. n ends at end·k/n.
  static StepTimes equal(long n, double end) {
    StepTimes s;
    s.n_ = static_cast<std::size_t>(n);
    s.end_ = end;
    return s;
  }
  /// The listed end times (solver.times).
  static StepTimes list(std::vector<double> times) {
    StepTimes s;
    s.list_ = std::move(times);
    return s;
  }

  std::size_t size() const { return list_.empty() ? n_ : list_.size(); }
  /// End time of step k = 0 .. size() − 1.
  double operator[](std::size_t k) const {
    return list_.empty() ? end_ * static_cast<double>(k + 1) / static_cast<double>(n_) : list_[k];
  }
  double back() const { return (*this)[size() - 1]; }
  /// Every end time, in order (tests and tools; the solver takes them one by one).
  std::vector<double> all() const {
    std::vector<double> t(size());
    for (std::size_t k = 0; k < t.size(); ++k) t[k] = (*this)[k];
    return t;
  }

 private:
  std::size_t n_ = 1;         ///< equal steps: their number
  double end_ = 1.0;          ///< equal steps: the end time
  std::vector<double> list_;  ///< listed end times; empty for equal steps
};

/// The iteration schemes of the formulation and Newton (solve/schemes.hpp); for elastic
/// materials they are the same single linear solve per step.
enum class SchemeKind {
  newton,
  variable_stiffness,        // 1: (2.32)-(2.34)
  initial_strain,            // 2: (2.35)-(2.37)
  initial_strain_stiffness,  // 3: (2.38)-(2.40)
  initial_stress,            // 4: (2.41)-(2.43)
  initial_stress_stiffness,  // 5: (2.44)-(2.46)
};

/// The one table of the schemes' names (solver.scheme), in the order of SchemeKind.
inline constexpr std::array<const char*, 6> scheme_names = {
    "newton",         "variable-stiffness",      "initial-strain", "initial-strain-stiffness",
    "initial-stress", "initial-stress-stiffness"};
inline const char* scheme_name(SchemeKind kind) {
  return scheme_names[static_cast<std::size_t>(kind)];
}

/// Which form of the curve variable-stiffness iterates on: stress σ̃ = Φ(ε̃) (2.33) or strain
/// ε̃ = F(σ̃) (2.34).
enum class CurveForm { stress, strain };

struct SolverSpec {
  enum class Linear { automatic, direct, iterative, petsc };
  SchemeKind scheme = SchemeKind::newton;
  CurveForm curve_form = CurveForm::stress;  ///< variable-stiffness only
  /// `formulation: hencky | report`. `hencky` (the default): the schemes with hencky's
  /// additions (the trial's flow direction, the elastic start, Anderson's mixing, the line
  /// search, the held plastic set, ...; docs/schemes.md). `report`: the five schemes iterate
  /// as the report writes them (solve/report_schemes.cpp), and the settings that would add
  /// one of hencky's strategies are refused.
  bool report = false;
  StepTimes times;  ///< end times of the steps
  /// Iteration limit per step: a number >= 1, or 0 for `auto` (the default): 50 for newton and
  /// variable-stiffness, 200 for the fixed-matrix schemes (auto_max_iterations,
  /// solve/iteration_policy.cpp).
  int max_iterations = 0;
  double tolerance = 1e-6;  ///< 0 < tolerance < 1
  /// Relaxation ω of the initial-strain schemes: a number > 0, or 0 for `auto` (the default):
  /// at each point the curve's slope at the iterate, ω = tan β / 3G (docs/schemes.md). Under
  /// `formulation: report` a number, 1 by default (the report's update, unrelaxed).
  double relaxation = 0;
  /// γ of the error correction (2.30), chosen per step as the report says: a number, or an
  /// expression of t evaluated at each step's end time; >= 0, and 0 turns the correction off.
  Expression correction{1.0};
  int cutback = 4;  ///< >= 0
  /// A plastic step whose largest displacement exceeds this fraction of the diagonal of the
  /// mesh's bounding box stops the run: the body has become a mechanism. > 0.
  double mechanism_limit = 0.05;
  /// newton only (`predictor: extrapolate | none`): start a step from the last step's
  /// displacement increment scaled to this step's length, when the new load does positive work
  /// on it; otherwise (and for the other schemes) from the converged state.
  bool extrapolate = true;
  /// `acceleration`: Anderson mixing of the fixed-matrix iterations, depth 8 for
  /// the initial strains and 5 for the initial stresses (src/solve/anderson.hpp,
  /// choose_policy). `auto` (the default) mixes wherever the scheme allows it
  /// (Scheme::allows_acceleration), `anderson` asks for it (an input error where the scheme does
  /// not allow it), `none` takes the scheme's own map unmixed (formulation: report is the
  /// report's plain iteration).
  enum class Acceleration { automatic, none, anderson };
  Acceleration acceleration = Acceleration::automatic;
  /// `line_search: auto | none`: `auto` (the default) scales each correction of
  /// variable-stiffness and newton after the first of a step by one secant step on the
  /// residual's work along it (LineSearch, solve/line_search.cpp); `none` takes the corrections
  /// whole, as the report.
  bool line_search = true;
  /// `geometry: small | updated`. `small` (the default): every step on the undeformed mesh.
  /// `updated`: each step on the configuration at its start, X + u(t), the report's ^(t)Ω,
  /// in updated Lagrangian form (CellDeformation: the step's Green strain, exact internal
  /// forces, objective stresses; docs/schemes.md, "Updated geometry").
  bool updated_geometry = false;
  /// `correction_form: previous | current`: R of the correction integrated over the
  /// configuration of the step before, (2.30), as the report chooses (the default), or over
  /// the configuration at t, (2.31). The same under `geometry: small`.
  bool correction_current = false;
  /// direct and iterative are the serial back ends; petsc (and every run on more than one MPI
  /// rank) the PETSc one; automatic (`auto`, the default) chooses between direct and petsc
  /// (solve/linear_choice.hpp).
  Linear linear = Linear::automatic;
  /// PETSc options of the case ("-ksp_type cg -pc_type hypre"), added before those of the
  /// command line (which win).
  std::string petsc_options;
};

/// An output request of a CalculiX deck run as the case (docs/ccx-decks.md): what MODEL.dat
/// (*NODE PRINT, *EL PRINT) and MODEL.frd (*NODE FILE, *EL FILE) hold over one of the deck's
/// steps.
struct DeckRequest {
  enum class Kind { node_print, el_print, node_file, el_file };
  Kind kind = Kind::node_print;
  /// A print request (MODEL.dat), not a file request (MODEL.frd).
  bool prints() const { return kind == Kind::node_print || kind == Kind::el_print; }
  std::string set;  ///< the NSET (ELSET) named, upper case; empty: every node (element)
  std::vector<std::string> variables;  ///< upper case, those hencky writes: U, RF, NT, S, PEEQ
  /// Every `frequency`-th increment of the step and its last one; 0: none.
  int frequency = 1;
  enum class Totals { no, yes, only } totals = Totals::no;  ///< RF's sum over the set
  double start = 0, end = 0;  ///< the deck step it belongs to, in the deck's total time
  SourceLocation where;
};

struct OutputSpec {
  std::filesystem::path dir;  ///< absolute; default <case dir>/<case stem>.out
  SourceLocation dir_where;   ///< key output.dir; the case file alone when it is the default
  int every = 1;              ///< >= 1; the last step is always written
  /// A checkpoint (output/checkpoint.hpp) every `checkpoint` converged steps, and at the last
  /// converged step of the run; 0 (`off`): none. Default: at every step whose fields are
  /// written (output.every).
  int checkpoint = -1;
  int checkpoint_keep = 0;  ///< the newest N checkpoints are kept; 0: all of them
  /// output.checkpoint resolved: every this many converged steps; 0: none.
  int checkpoint_every() const { return checkpoint < 0 ? every : checkpoint; }
  std::vector<ProbeSpec> probes;
  /// `iterations: true`: iterations.csv, one row per iterate of every step attempted (its
  /// measures, and the probes' stress and ε̃^{e+p} at the iterate).
  bool iterations = false;
  std::vector<std::string> reactions;  ///< regions that have a displacement (or a heat
                                       ///< temperature) condition
  std::vector<SourceLocation> reaction_where;
  std::vector<std::string> heat_flows;  ///< regions whose heat flow is written (heat_flows)
  std::vector<SourceLocation> heat_flow_where;
  /// A deck run as the case: its output requests, and the names of the files they go to in the
  /// output directory (MODEL.dat, MODEL.frd); empty for a case file.
  std::vector<DeckRequest> deck_requests;
  std::string deck_dat, deck_frd;
};

/// A region named by the mesh's labels (mesh.regions): nodes by their labels (node tags), volume
/// elements by theirs, or element faces as (element label, face number S1 .. S6 of the Abaqus
/// and CalculiX manuals). Exactly one of the three lists is given.
struct LabelRegionSpec {
  std::string name;
  std::vector<long> nodes, elements;
  std::vector<std::pair<long, int>> faces;
  SourceLocation where;                    ///< the entry mesh.regions[i]
  std::vector<SourceLocation> item_where;  ///< each label (face) given, for messages
};

struct MeshSpec {
  std::filesystem::path file;  ///< absolute; exists; .msh or .geo
  int order = 0;               ///< 0: as in the file, else 1 or 2
  double scale = 1.0;          ///< > 0
  SourceLocation where;        ///< location of the file name (key mesh.file)
  /// `split: true`: the mesh is the files Gmsh split it into (`-part N -part_split`), `file`'s
  /// stem with _1 .. _N, one per MPI rank (piece_file); `pieces` is N (each exists).
  bool split = false;
  int pieces = 0;
  std::vector<LabelRegionSpec> regions;  ///< mesh.regions: regions named by labels
};

/// File k (from 0) of a split mesh: cyl.msh's are cyl_1.msh, cyl_2.msh, ...
inline std::filesystem::path piece_file(const MeshSpec& mesh, int k) {
  return mesh.file.parent_path() /
         (mesh.file.stem().string() + "_" + std::to_string(k + 1) + mesh.file.extension().string());
}

struct Case {
  std::filesystem::path file;  ///< the case file, absolute
  std::string title;           ///< default: the case file name without extension
  MeshSpec mesh;
  std::vector<MaterialSpec> materials;  ///< at least one
  TemperatureSpec temperature;
  HeatSpec heat;
  std::vector<BoundarySpec> boundary;
  std::optional<std::array<Expression, 3>> body_force;
  std::vector<ContactSpec> contact;
  SolverSpec solver;
  OutputSpec output;
};

}  // namespace hencky
