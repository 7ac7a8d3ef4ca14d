#pragma once
// The analysis model: the validated case bound to the mesh. Everything here is checked
// against the mesh once (regions, materials, element shapes, probes, temperature nodes) so
// that the step loop meets no input error.
//
// Model's definitions: model.cpp (construction, materials, cells, probes and reactions, the
// points each rank holds), model_loads.cpp (displacement, load and heat conditions; the loads
// at a time), model_temperature.cpp (temperatures and their range checks), model_contact.cpp
// (contact surfaces and points) and model_join.cpp (a part model joined with the other ranks,
// the cells the ranks agree on).
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "contact/contact.hpp"
#include "core/log.hpp"
#include "linalg/assembler.hpp"
#include "linalg/sparse_solver.hpp"
#include "material/elastic.hpp"
#include "material/hardening.hpp"
#include "material/point_law.hpp"
#include "mesh/mesh.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/nodal_layout.hpp"
#include "parallel/partition.hpp"
#include "spec/case.hpp"

namespace hencky {

struct MaterialModel {
  const MaterialSpec* spec;
  /// The hardening curve of a plastic material (shared: MaterialModel is copied).
  std::shared_ptr<const Hardening> hardening;
  bool elastic_unloading = true;
  /// The point law of a plastic material (material/point_law.hpp): von Mises with the isotropic
  /// curve, or the law its keys selected.
  std::shared_ptr<const PointLaw> law;
  bool plastic() const { return hardening != nullptr; }
  /// E, ν, α at temperature T; *outside is set when T leaves a property's table. Thread-safe.
  ElasticConstants at(double T, bool* outside = nullptr) const;
  /// Warns (once per message) when [T_min, T_max] leaves a property's table.
  void warn_outside(double T_min, double T_max, Log& log) const;
};

/// A boundary face loaded by pressure, traction or force.
struct FaceLoad {
  int face;            ///< index into Mesh::faces
  int boundary;        ///< index into Case::boundary
  double sign;         ///< +1 when the face's own normal points out of the body, else -1
  double scale = 1.0;  ///< 1 / region area for a total force, else 1
};

/// A face of a heat condition (flux, convection, radiation) in the volume cell that owns it:
/// the heat solver integrates it with that cell, so that its matrix goes in with the cell's.
struct HeatFace {
  int face;                                         ///< index into Mesh::faces
  int boundary;                                     ///< index into HeatSpec::boundary
  int cell;                                         ///< the volume cell the face bounds
  std::array<std::int8_t, max_cell_nodes> local{};  ///< the cell's index of each face node
};

struct Probe {
  const ProbeSpec* spec;
  int cell;
  double xi[3];
};

struct ReactionRegion {
  std::string name;
  const Region* region;
  bool force = true;  ///< some node has a prescribed displacement: reaction.<name>.x|y|z
  /// A heat.boundary temperature condition names the region: reaction.<name>.heat, the heat
  /// into the body through its nodes (the sum of those conditions' flows).
  bool heat = false;
};

class Model {
 public:
  /// Binds the case to the mesh; throws InputError for everything that does not fit.
  Model(const Case& c, Mesh mesh, Log& log);
  /// A rank's part of a distributed model (issue 21, docs/parallel.md): binds the case to the
  /// part alone. The checks that need the whole mesh (a region empty, a probe outside the
  /// mesh, a body without supports) and the figures of the whole (a total force's area, the
  /// owner of a probe, the global counts) come with join(), which must follow on every rank.
  /// Not collective: a rank that throws here lets the others know before join (app/together.hpp,
  /// together()).
  Model(const Case& c, MeshPart part, Log& log);
  /// Completes a part model with what the ranks know together (above), and makes the whole
  /// model's checks with the same messages as a whole mesh's: every rank throws the same
  /// InputError (the rigid motions of check_held too; its warnings go to `log`). Collective.
  void join(Log& log);
  /// The mesh, moved out: what the rank that read it sends out in parts once the whole model
  /// has checked it. The model is of no use after.
  Mesh take_mesh() && { return std::move(mesh_); }
  /// The part's numbering against the whole mesh (its `mesh` is empty: the model holds it),
  /// or nullptr for a model of the whole mesh.
  const MeshPart* part() const { return dist_.part ? &*dist_.part : nullptr; }
  /// The ghost exchange of a part's nodes (after join), or nullptr.
  const NodeExchange* exchange() const { return dist_.exchange.get(); }
  /// A cell the ranks agree on, from what each found (its own index of a cell, or -1): the
  /// lowest found, as agreed_index() numbers it (Model::cell_facts tells its tag and
  /// material). -1 when no rank found one. Collective.
  int agreed_cell(int found) const;
  /// This model's index of its cell where the mesh is whole on every rank, else the whole
  /// mesh's.
  int agreed_index(int cell) const { return dist_.part ? dist_.part->global_cell[cell] : cell; }
  struct CellFacts {
    long tag = -1;      ///< the mesh file's number
    int material = -1;  ///< index into materials()
  };
  /// The tag and material of an agreed cell (collective on a distributed mesh: its owner says).
  CellFacts cell_facts(int agreed) const;
  /// The whole model's counts: nodes, volume cells and free dofs (this model's own without a
  /// part).
  long long global_nodes() const { return dist_.global[0]; }
  long long global_cells() const { return dist_.global[1]; }
  long long global_free() const { return dist_.global[2]; }
  /// The length of the whole mesh's cell connectivity (its cells' node references).
  long long global_connectivity() const { return dist_.global[3]; }

  const Case& spec() const { return *case_; }
  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return dofs_; }
  const Assembler& assembler() const { return *assembler_; }
  /// The mesh's node-graph factor (linalg/sparse_solver.hpp, estimate_factor), analysed on
  /// first use: solver.linear: auto's prediction for the displacement and the temperature, and
  /// the ordering a direct back end then uses.
  const FactorEstimate& node_factor() const;
  // Integration points are stored per rank, cell by cell, for the cells this rank holds
  // (hold_points); one rank holds every cell.
  /// This rank's points: the length of a State's integration-point arrays.
  int n_points() const { return points_.offset.back(); }
  /// Where cell's points start in this rank's arrays; a cell held by another rank has none
  /// (point_offset(cell) == point_offset(cell + 1)).
  int point_offset(int cell) const { return points_.offset[cell]; }
  bool holds_points(int cell) const { return points_.offset[cell + 1] > points_.offset[cell]; }
  /// The points of the whole model, over all ranks.
  int total_points() const { return points_.total; }
  /// On a part (after join): where cell's points start in the whole mesh's order, the order
  /// of a checkpoint.
  long long whole_point_offset(int cell) const { return points_.whole_offset[cell]; }
  /// The split of the mesh over the MPI ranks (one part on one rank): this rank then holds the
  /// points of its own cells (hold_points). Call before any State is made.
  void set_partition(Partition partition);
  const Partition& partition() const { return dist_.partition; }
  /// How this rank's nodal vectors stand to the whole model's: whole on one rank, replicated
  /// once set_partition split the cells over several.
  const NodalLayout& layout() const { return dist_.layout; }
  const MaterialModel& material_of(int cell) const { return materials_[cell_material_[cell]]; }
  int material_index(int cell) const { return cell_material_[cell]; }
  const std::vector<MaterialModel>& materials() const { return materials_; }
  /// Every probe of the case, in its order; on a part, a probe in another rank's cell has
  /// cell -1.
  const std::vector<Probe>& probes() const { return probes_; }
  const std::vector<ReactionRegion>& reaction_regions() const { return reactions_; }
  double reference_temperature() const { return temperature_.reference; }
  bool has_temperature() const { return case_->temperature.given; }
  /// The case's contacts, bound to the mesh (empty without a contact section).
  const std::vector<ContactBody>& contacts() const { return contacts_; }
  /// Some material has a hardening curve.
  bool has_plasticity() const;
  /// The numbers of a point law's state each integration point keeps (State::internal): the
  /// largest over the materials' laws, 0 when no law has internal variables.
  int law_state_size() const { return points_.law_state; }
  /// The internal variables of that state, in its order (PointLaw::variables): the outputs'
  /// names. A model holds one law with internal variables at most (bind_materials).
  std::span<const LawVariable> law_variables() const {
    return points_.stateful ? points_.stateful->variables() : std::span<const LawVariable>();
  }
  /// Whether region names match without regard to case: those of an Abaqus/CalculiX deck do,
  /// as in Abaqus (input/inp_reader.hpp); Gmsh's physical names do not.
  bool region_names_ignore_case() const;

  // Heat conduction (the heat section; empty without one).
  bool has_heat() const { return case_->heat.given; }
  /// The temperature dofs, one per node: prescribed where a heat temperature condition holds.
  const DofMap& heat_dofs() const { return heat_.dofs; }
  const Assembler& heat_assembler() const { return *heat_.assembler; }
  /// Per node, the heat.boundary entry that prescribes its temperature (the last one listed
  /// that holds the node), or -1.
  const std::vector<int>& heat_fixed() const { return heat_.fixed; }
  /// Faces of the flux, convection and radiation conditions, and for each cell where its faces
  /// start in that list (CSR: cell c's are heat_faces()[heat_face_start(c) ..
  /// heat_face_start(c + 1)).
  const std::vector<HeatFace>& heat_faces() const { return heat_.faces; }
  int heat_face_start(int cell) const { return heat_.face_start[cell]; }
  /// The nodes of the nodal_flux entries, each with its entry (heat.boundary's index): this
  /// rank's own nodes on a distributed mesh, every node otherwise.
  const std::vector<std::pair<int, int>>& heat_nodal() const { return heat_.nodal; }

  /// Nodal temperature at time t (T_ref everywhere without a temperature section) of a field or
  /// a file; temperatures from a heat analysis are the HeatSolver's.
  void nodal_temperature(double t, std::vector<double>& T) const;
  /// Prescribed displacement at time t written into the prescribed entries of u (3 per node).
  void prescribed_displacement(double t, std::vector<double>& u) const;
  /// External nodal forces at time t (pressure, traction, force, body force), 3 per node.
  /// A load whose nodal forces overflow is an InputError at its key. `config`: the nodes'
  /// coordinates the faces are loaded on (geometry: updated), else the mesh's; body forces stay
  /// per unit undeformed volume.
  void external_forces(double t, std::vector<double>& f,
                       const std::vector<Vec3>* config = nullptr) const;

  /// Whether the constants k of material `mi` at temperature T give a thermal strain
  /// α(T)·T − α(T_ref)·T_ref that, and whose stress when fully restrained (E/(1 − 2ν) times
  /// it), are finite numbers. Thread-safe.
  bool thermal_in_range(int mi, const ElasticConstants& k, double T) const;
  /// The InputError, at the temperature field's key, for a temperature T of `cell` at time t
  /// that thermal_in_range refuses (t NaN: at every time).
  [[noreturn]] void thermal_out_of_range(int cell, double T, double t) const;
  /// The same for a cell of `facts` (any rank's).
  [[noreturn]] void thermal_out_of_range(const CellFacts& facts, double T, double t) const;
  /// The thermal strain α(T)·T − α(T_ref)·T_ref (volumetric) of `cell`'s material with the
  /// constants k at T: the strain of (1.14) accumulated from the reference state.
  double thermal_strain(int cell, const ElasticConstants& k, double T) const {
    return k.thermal_strain(T) - temperature_.reference_strain[cell_material_[cell]];
  }

 private:
  /// external_forces of this rank's faces and cells (the whole model's without a part).
  void own_external_forces(double t, std::vector<double>& f, const std::vector<Vec3>* config) const;
  /// This rank stores the points of the cells with held[cell] != 0 only.
  void hold_points(const std::vector<char>& held);
  mutable std::optional<FactorEstimate> node_factor_;
  void bind(Log& log);
  void bind_materials(Log& log);
  void check_cells();
  void bind_boundary();
  void bind_temperature();
  void check_temperature_range();
  void bind_outputs();
  void bind_contact();
  /// Every connected body is held against its six rigid motions by its displacement
  /// conditions, or by contact (a warning); else an InputError naming the body and the motions
  /// (model_held.cpp). On a part, with the other ranks' pieces of the bodies (collective, from
  /// join).
  void check_held(Log& log) const;
  /// A part's contact points, bound together (join): every copy of a point has the whole
  /// model's area, element size and stiffness. Collective.
  void bind_contact_of_part();
  /// Adds to each point's stiffness scale this mesh's cells' share at it.
  void add_contact_stiffness(std::vector<ContactPoint>& points) const;
  /// Sets each point's starting gap, and returns the message for the first point (of those
  /// whose node `node_owner` gives this rank, when given) that starts inside the surface by
  /// more than allowed, or "".
  std::string start_contact(ContactBody& body, const std::vector<int>* node_owner) const;
  void bind_heat();
  /// The volume cell that owns boundary face f (holds all its corner nodes); -1 when none
  /// does, -2 when two do (an inner face). nc_*: node_cell_incidence of the cells.
  int face_owner(int f, const std::vector<int>& nc_ptr, const std::vector<int>& nc_idx) const;
  /// face_owner, or the input error (at `where`) that face f of `region` is no outer face, for
  /// which `what` ("a pressure must be applied") then says what needs one.
  int outer_face_owner(int f, const std::vector<int>& nc_ptr, const std::vector<int>& nc_idx,
                       const SourceLocation& where, const std::string& region,
                       const std::string& what) const;
  /// join()'s checks of what no part can judge alone: a region empty on every rank, a body
  /// without supports or without a free dof. Collective.
  void check_whole() const;
  /// join()'s check that every loaded face is on the outer surface where its two cells (an
  /// inner face's) are on two ranks: each finds one cell at it. Collective.
  void check_outer_faces() const;
  void check_scheme(const MaterialSpec& mat, const PointLaw& law) const;
  void bind_law_state(const MaterialSpec& mat, const std::shared_ptr<const PointLaw>& law);
  const Region& find_region(const std::string& name, const SourceLocation& where, int dim_min,
                            int dim_max, const char* what) const;

  /// How this model stands to the MPI ranks.
  struct Distribution {
    std::optional<MeshPart> part;        ///< a part model's numbering, else empty
    long long global[4] = {0, 0, 0, 0};  ///< the whole model's counts (global_nodes() ...)
    /// The ranks share one NodeExchange over the part's nodes (its layout's).
    std::shared_ptr<const NodeExchange> exchange;
    Partition partition;
    NodalLayout layout;
  };
  /// Where each cell's integration points are stored (hold_points).
  struct PointLayout {
    std::vector<int> offset;              ///< this rank's, per cell and one past the last
    std::vector<long long> whole_offset;  ///< a part's, in the whole mesh's order (join)
    int total = 0;                        ///< over all ranks
    int law_state = 0;                    ///< law_state_size()
    std::shared_ptr<const PointLaw> stateful;  ///< the law with internal variables, if any
  };
  struct PrescribedDof {
    int dof;
    const Expression* value;
  };
  /// The displacement and load conditions bound to the mesh (bind_boundary).
  struct Loads {
    std::vector<PrescribedDof> prescribed;
    std::vector<FaceLoad> faces;
    /// nodal_force: each node of its region (on a part, the nodes it owns), by index into
    /// Case::boundary.
    std::vector<std::pair<int, int>> nodal;
    /// On a part: this rank's area of each force boundary's region (join sums them), by index
    /// into Case::boundary.
    std::vector<std::pair<int, double>> part_areas;
  };
  /// The heat section bound to the mesh (bind_heat): heat_dofs() ... heat_face_start().
  struct HeatBinding {
    DofMap dofs;
    std::unique_ptr<Assembler> assembler;
    std::vector<int> fixed;
    std::vector<HeatFace> faces;
    std::vector<int> face_start;
    std::vector<std::pair<int, int>> nodal;  ///< (node, boundary entry) of nodal_flux, own nodes
  };
  /// The temperature section bound to the mesh and the materials.
  struct Temperatures {
    std::vector<int> row;                  ///< row of the temperature file for each node
    std::vector<double> reference_strain;  ///< α(T_ref)·T_ref of each material
    double reference = 0;                  ///< T_ref (0 without a temperature section)
  };

  const Case* case_;
  Mesh mesh_;
  Distribution dist_;
  std::vector<MaterialModel> materials_;
  std::vector<int> cell_material_;
  PointLayout points_;
  DofMap dofs_;
  std::unique_ptr<Assembler> assembler_;
  Loads loads_;
  std::vector<Probe> probes_;
  std::vector<ReactionRegion> reactions_;
  std::vector<ContactBody> contacts_;
  HeatBinding heat_;
  Temperatures temperature_;
};

}  // namespace hencky
