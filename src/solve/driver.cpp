#include "solve/driver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <optional>

#include "contact/surface_type.hpp"
#include "core/timer.hpp"
#include "linalg/petsc_solver.hpp"
#include "linalg/serial_system.hpp"
#include "parallel/mpi.hpp"
#include "parallel/partition.hpp"
#include "solve/linear_choice.hpp"

namespace hencky {

std::string describe_unknowns(const Model& model, long long free, long long nodes) {
  return model.spec().heat.only ? fmt::format("{} temperatures", nodes)
                                : fmt::format("{} unknowns", free);
}

std::string describe_mesh(const Mesh& mesh) {
  std::map<std::string, long long> by_type;
  for (auto t : mesh.cells.type) ++by_type[std::string(cell_name(t))];
  return describe_counts(mesh.n_nodes(), mesh.cells.size(), by_type);
}

std::string describe_counts(long long nodes, long long cells,
                            const std::map<std::string, long long>& by_type) {
  std::string s = fmt::format("{} nodes, {} elements (", nodes, cells);
  bool first = true;
  for (auto& [name, n] : by_type) {
    s += fmt::format("{}{} {}", first ? "" : ", ", n, name);
    first = false;
  }
  return s + ")";
}

std::vector<std::string> describe_contact(const Model& model) {
  std::vector<std::string> out;
  for (const ContactBody& b : model.contacts()) {
    const ContactSpec& s = *b.spec;
    double k_lo = INFINITY, k_hi = 0;
    long long points = 0, touching = 0, quadratic = 0;
    const MeshPart* part = model.part();  // each point counted by its node's owner
    for (std::size_t i = 0; i < b.points.size(); ++i) {
      if (part && part->node_owner[b.points[i].node] != par::rank()) continue;
      const double k = b.initial_kappa(static_cast<int>(i));
      k_lo = std::min(k_lo, k);
      k_hi = std::max(k_hi, k);
      ++points;
      touching += b.touches_at_start(static_cast<int>(i));
      quadratic += b.points[i].terms == 3;
    }
    if (part) {
      points = par::sum(points);
      touching = par::sum(touching);
      quadratic = par::sum(quadratic);
      par::min_in_place(std::span<double>(&k_lo, 1));
      par::max_in_place(std::span<double>(&k_hi, 1));
    }
    std::string line =
        fmt::format("contact '{}': {} nodes of '{}' ({} touching at t = 0{}) on {}", s.name, points,
                    s.nodes, touching, quadratic ? fmt::format(", {} mid-edge", quadratic) : "",
                    surface_type(s.surface.type).noun);
    line += s.stiffness ? fmt::format("; κ = {:.3g}", *s.stiffness)
                        : fmt::format("; κ auto {:.3g} .. {:.3g}", k_lo, k_hi);
    line += fmt::format(", allowed penetration {:g} of the element size", s.penetration);
    out.push_back(line);
  }
  return out;
}

namespace {

/// The system of a model whose every displacement is prescribed (issue 23: a material-point
/// test drives its elements through a strain history): no unknown, so nothing to assemble,
/// factorize or solve. The step loop runs as usual: its iterates are the prescribed
/// displacements, the point laws converge on them, and the reactions are the internal forces.
class NoUnknowns final : public LinearSystem {
 public:
  explicit NoUnknowns(std::optional<std::vector<char>> own) : own_(std::move(own)) {
    stats_.description = "none: every degree of freedom is prescribed";
  }
  void assemble_cells(const CellMatrix&) override {}
  void keep_cells() override {}
  bool restore_cells() override { return true; }
  void add_block(int, int, const Mat3&) override {}
  void factorize() override {}
  void solve(std::span<const double>, std::span<double>) override {}
  void set_relative_tolerance(double) override {}
  std::vector<std::string> unused_options() const override { return {}; }
  const std::vector<char>* own_cells() const override { return own_ ? &*own_ : nullptr; }
  const LinearSolverStats& stats() const override { return stats_; }

 private:
  std::optional<std::vector<char>> own_;
  LinearSolverStats stats_;
};

/// The case's back end for the system of `assembler` and `dofs` (the displacement's or the
/// temperature's); `model` is given for the displacement only: it then logs the choice and
/// holds the points of this rank's cells.
std::unique_ptr<LinearSystem> make_system(const Model& spec_model, Model* model,
                                          const Assembler& assembler, const DofMap& dofs, Log& log,
                                          const std::string& petsc_options) {
  const SolverSpec& s = spec_model.spec().solver;
  const int ranks = par::size();
  if (model && spec_model.global_free() == 0) {
    log.info(
        "linear solver: none, every degree of freedom is prescribed (the points follow the "
        "prescribed displacements; the reactions are their internal forces)");
    if (ranks == 1 || spec_model.part()) return std::make_unique<NoUnknowns>(std::nullopt);
    Partition part = partition_mesh(spec_model.mesh(), ranks, par::rank());
    std::vector<char> own = part.owned_cell;
    model->set_partition(std::move(part));
    return std::make_unique<NoUnknowns>(std::move(own));
  }
  SolverSpec::Linear linear = s.linear;
  std::vector<std::int64_t> node_order;  // of the factor estimate, for the factorization
  if (linear == SolverSpec::Linear::automatic) {
    LinearChoiceInputs in;
    in.unknowns = dofs.n_free;
    in.per_node = dofs.per_node;
    in.nonlinear =
        dofs.per_node == 3 && (spec_model.has_plasticity() || !spec_model.contacts().empty());
    in.ranks = ranks;
    in.available_bytes = available_memory_bytes();
    const LinearChoiceRule rule = LinearChoiceRule::from_environment();
    std::string estimate;
    if (wants_factor_estimate(in, rule)) {
      const Clock::time_point t0 = Clock::now();
      const FactorEstimate& f = spec_model.node_factor();  // once for both systems
      in.factor_flops = f.flops_for(dofs.per_node);
      in.factor_entries = f.entries_for(dofs.per_node);
      node_order = f.node_order;
      estimate =
          fmt::format(" (factor predicted by a symbolic analysis of the node graph in {:.2f} s)",
                      seconds_since(t0));
    }
    const LinearChoice choice = choose_linear(in, rule);
    linear = choice.linear;
    log.info("linear solver{} (solver.linear: auto): {}; {}{}",
             model ? "" : " of the heat analysis",
             linear == SolverSpec::Linear::direct ? "CHOLMOD sparse Cholesky" : "PETSc CG + GAMG",
             choice.reason, estimate);
  }
  if (linear != SolverSpec::Linear::petsc && ranks == 1)
    return make_serial_system(assembler, dofs,
                              linear == SolverSpec::Linear::iterative ? LinearSolverKind::iterative
                                                                      : LinearSolverKind::direct,
                              1e-10, std::move(node_order));
  const PetscPreset preset =
      linear == SolverSpec::Linear::direct ? PetscPreset::mumps : PetscPreset::gamg;
  if (linear != SolverSpec::Linear::petsc && model)
    log.info("{} MPI ranks: the PETSc back end with {} replaces solver.linear: {}", ranks,
             preset == PetscPreset::mumps ? "MUMPS (direct)" : "CG + GAMG (iterative)",
             linear == SolverSpec::Linear::direct ? "direct" : "iterative");
  const std::string options = s.petsc_options.empty() || petsc_options.empty()
                                  ? s.petsc_options + petsc_options
                                  : s.petsc_options + " " + petsc_options;
  const auto petsc = [&](Partition part, std::optional<PetscPart> piece) {
    try {
      return std::make_unique<PetscSolver>(spec_model.mesh(), dofs, assembler, std::move(part),
                                           preset, options, 1e-10, piece);
    } catch (const std::invalid_argument& e) {
      throw InputError(
          SourceLocation{spec_model.spec().file.string(), 0, 0, "solver.petsc_options"},
          std::string(e.what()) + " (from solver.petsc_options and --petsc)");
    }
  };
  // A distributed mesh: the model is this rank's part, split when it was read.
  if (const MeshPart* p = spec_model.part())
    return petsc(spec_model.partition(), PetscPart{*p, *spec_model.exchange()});
  Partition part = partition_mesh(spec_model.mesh(), ranks, par::rank());
  if (ranks > 1 && model)
    log.info("partition: {} ranks, {} .. {} elements and {} .. {} nodes per rank", ranks,
             par::min(part.owned_cells), par::max(part.owned_cells), par::min(part.owned_nodes),
             par::max(part.owned_nodes));
  if (ranks > 1 && model) model->set_partition(part);
  return petsc(std::move(part), std::nullopt);
}

}  // namespace

std::unique_ptr<LinearSystem> make_run_solver(Model& model, Log& log,
                                              const std::string& petsc_options) {
  return make_system(model, &model, model.assembler(), model.dofs(), log, petsc_options);
}

std::unique_ptr<HeatSolver> make_heat_solver(const Model& model, Log& log,
                                             const std::string& petsc_options) {
  if (!model.has_heat()) return nullptr;
  return std::make_unique<HeatSolver>(
      model,
      [&](const Assembler& assembler, const DofMap& dofs) {
        return make_system(model, nullptr, assembler, dofs, log, petsc_options);
      },
      log);
}

}  // namespace hencky
