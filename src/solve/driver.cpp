#include "solve/driver.hpp"

#include <fmt/format.h>

#include <chrono>
#include <map>

#include "io/gmsh_reader.hpp"

namespace hencky {

LoadedCase load_case(const std::filesystem::path& case_file, Log& log) {
  using Clock = std::chrono::steady_clock;
  LoadedCase l;
  l.spec = std::make_unique<Case>(read_case(case_file));
  auto t0 = Clock::now();
  MeshReadOptions opt;
  opt.order = l.spec->mesh.order;
  opt.scale = l.spec->mesh.scale;
  std::vector<std::string> gmsh_log;
  Mesh mesh = read_gmsh(l.spec->mesh.file, opt, &gmsh_log);
  for (const auto& line : gmsh_log)
    if (line.rfind("Warning", 0) == 0) log.warn("Gmsh: " + line);
  l.mesh_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  l.model = std::make_unique<Model>(*l.spec, std::move(mesh), log);
  l.setup_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return l;
}

std::string describe_mesh(const Mesh& mesh) {
  std::map<std::string, int> by_type;
  for (auto t : mesh.cells.type) ++by_type[std::string(cell_name(t))];
  std::string s = fmt::format("{} nodes, {} elements (", mesh.n_nodes(), mesh.cells.size());
  bool first = true;
  for (auto& [name, n] : by_type) {
    s += fmt::format("{}{} {}", first ? "" : ", ", n, name);
    first = false;
  }
  return s + ")";
}

std::unique_ptr<InProcessRun> run_in_process(const std::filesystem::path& case_file, Log& log) {
  auto r = std::make_unique<InProcessRun>();
  r->loaded = load_case(case_file, log);
  auto solver = make_linear_solver(r->loaded.spec->solver.linear == SolverSpec::Linear::iterative
                                       ? LinearSolverKind::iterative
                                       : LinearSolverKind::direct);
  Timings timings;
  r->result = run_analysis(*r->loaded.model, *solver, log, timings, r->states);
  r->solver_stats = solver->stats();
  return r;
}

}  // namespace hencky
