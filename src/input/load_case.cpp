#include "input/load_case.hpp"

#include "core/timer.hpp"
#include "input/case_reader.hpp"
#include "input/gmsh_reader.hpp"
#include "input/inp_case.hpp"
#include "input/inp_reader.hpp"
#include "input/label_regions.hpp"

namespace hencky {

std::vector<std::filesystem::path> piece_files(const MeshSpec& mesh) {
  std::vector<std::filesystem::path> files;
  for (int k = 0; k < mesh.pieces; ++k) files.push_back(piece_file(mesh, k));
  return files;
}

LoadedCase load_case(const std::filesystem::path& case_file, Log& log) {
  return load_case(std::make_unique<Case>(read_case(case_file)), log);
}

namespace {

/// The case's mesh, read (or meshed), its readers' warnings logged.
Mesh read_mesh(const Case& spec, Log& log) {
  if (is_inp_file(spec.file)) {  // a deck run as a case: its mesh with the history's regions
    DeckRead deck = read_deck(spec.file);
    for (const auto& line : deck.warnings) log.warn(line);
    return std::move(deck.mesh);
  }
  MeshReadOptions opt;
  opt.order = spec.mesh.order;
  opt.scale = spec.mesh.scale;
  std::vector<std::string> gmsh_log;
  // A split mesh read whole (one rank, or ranks other than its files): its files together.
  std::vector<std::string> inp_warnings;
  Mesh mesh = spec.mesh.split               ? read_pieces(piece_files(spec.mesh), opt)
              : is_inp_file(spec.mesh.file) ? read_inp(spec.mesh.file, opt, &inp_warnings)
                                            : read_gmsh(spec.mesh.file, opt, &gmsh_log);
  for (const auto& line : gmsh_log)
    if (line.rfind("Warning", 0) == 0) log.warn("Gmsh: " + line);
  for (const auto& line : inp_warnings) log.warn(line);
  add_label_regions(mesh, spec.mesh.regions, is_inp_file(spec.mesh.file));
  return mesh;
}

}  // namespace

LoadedCase load_case(std::unique_ptr<Case> spec, Log& log) {
  LoadedCase l;
  l.spec = std::move(spec);
  Mesh mesh;
  {
    const ScopedTimer timer(l.mesh_seconds);
    mesh = read_mesh(*l.spec, log);
  }
  {
    const ScopedTimer timer(l.setup_seconds);
    l.model = std::make_unique<Model>(*l.spec, std::move(mesh), log);
  }
  return l;
}

std::unique_ptr<InProcessRun> run_in_process(const std::filesystem::path& case_file, Log& log,
                                             const std::string& petsc_options) {
  auto r = std::make_unique<InProcessRun>();
  r->loaded = load_case(case_file, log);
  auto solver = make_run_solver(*r->loaded.model, log, petsc_options);
  auto heat = make_heat_solver(*r->loaded.model, log, petsc_options);
  Timings timings;
  r->result = run_analysis(*r->loaded.model, *solver, log, timings, r->states, heat.get());
  r->solver_stats = solver->stats();
  if (heat) {
    r->heat_steps = heat->steps();
    r->heat_iterations = heat->iterations();
    r->heat_gmres_iterations = heat->gmres_iterations();
  }
  return r;
}

}  // namespace hencky
