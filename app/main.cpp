// hencky: command line (see docs/cli.md and the contract CASE_FORMAT.md).
// Exit status: 0 converged, 1 bad input, 2 a step did not converge, 3 internal error.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>

#include "hencky/version.hpp"
#include "io/case.hpp"
#include "io/log.hpp"
#include "io/results.hpp"
#include "solve/analysis.hpp"
#include "solve/driver.hpp"

namespace {
using namespace hencky;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

long peak_memory_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<long>(u.ru_maxrss) * 1024;
}

int run(const std::string& case_path, const std::string& out_dir, bool quiet) {
  const auto t_start = Clock::now();
  Log log;
  log.quiet = quiet;
  LoadedCase l = load_case(case_path, log);
  const Model& model = *l.model;
  const Case& c = *l.spec;
  const fs::path dir = out_dir.empty() ? c.output.dir : fs::absolute(out_dir);
  log.info("hencky {}: {}", HENCKY_VERSION, c.title);
  log.info("mesh: {}; {} unknowns", describe_mesh(model.mesh()), model.dofs().n_free);
  for (const auto& line : describe_contact(model)) log.info("{}", line);

  auto solver = make_linear_solver(c.solver.linear == SolverSpec::Linear::iterative
                                       ? LinearSolverKind::iterative
                                       : LinearSolverKind::direct);
  ResultWriter writer(model, dir, log);
  Timings timings;
  AnalysisResult result;
  try {
    result = run_analysis(model, *solver, log, timings, writer);
  } catch (const InputError&) {
    writer.abandon();  // bad input: nothing is overwritten or left behind
    throw;
  }
  const auto& st = solver->stats();
  nlohmann::json summary;
  summary["hencky"] = HENCKY_VERSION;
  summary["title"] = c.title;
  summary["status"] = result.status == AnalysisStatus::converged ? "converged" : "not-converged";
  if (!result.failure.empty()) summary["failure"] = result.failure;
  summary["steps"] = result.steps;
  summary["iterations"] = result.iterations;
  summary["factorizations"] = result.factorizations;
  summary["scheme"] = c.solver.scheme;
  summary["dofs"] = model.dofs().n_free;
  summary["nodes"] = model.mesh().n_nodes();
  summary["elements"] = model.mesh().cells.size();
  summary["integration_points"] = model.n_points();
  summary["threads"] = omp_get_max_threads();
  summary["linear_solver"] = {{"method", st.description},
                              {"analyses", st.n_analyses},
                              {"factorizations", st.n_factorizations},
                              {"solves", st.n_solves},
                              {"factor_flops", st.factor_flops},
                              {"factor_nonzeros", st.factor_nnz},
                              {"iterations", st.iterations}};
  if (st.n_factorizations > 0 && timings.factorization > 0)
    summary["linear_solver"]["factor_gflops_per_second"] =
        st.factor_flops * st.n_factorizations / timings.factorization * 1e-9;
  summary["warnings"] = log.warnings();
  for (auto& [k, v] : writer.final_values().items()) summary[k] = v;
  summary["wall_seconds"] = {{"mesh", l.mesh_seconds},     {"setup", l.setup_seconds},
                             {"assembly", timings.assembly}, {"factorization", timings.factorization},
                             {"solve", timings.solve},       {"material", timings.material},
                             {"output", timings.output},     {"contact", timings.contact},
                             {"total", since(t_start)}};
  summary["peak_memory_bytes"] = peak_memory_bytes();
  writer.finish(summary);
  log.info("{} in {:.2f} s ({} steps, {} iterations); results in {}",
           result.status == AnalysisStatus::converged ? "converged" : "stopped", since(t_start),
           result.steps, result.iterations, dir.string());
  return result.status == AnalysisStatus::converged ? 0 : 2;
}

int check(const std::string& case_path) {
  Log log;
  LoadedCase l = load_case(case_path, log);
  const Model& m = *l.model;
  std::cout << fmt::format("{}: ok\n  mesh: {}\n  unknowns: {}\n  steps: {}\n", case_path,
                           describe_mesh(m.mesh()), m.dofs().n_free, l.spec->solver.times.size());
  std::cout << "  regions:";
  for (const auto& r : m.mesh().regions) std::cout << fmt::format(" {} ({}D)", r.name, r.dim);
  std::cout << "\n";
  for (const auto& line : describe_contact(m)) std::cout << "  " << line << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hencky: thermo-elastic finite-element analysis of 3D structures"};
  app.set_version_flag("--version", std::string("hencky ") + HENCKY_VERSION);
  app.require_subcommand(1);
  std::string case_path, out_dir;
  bool quiet = false;
  int threads = 0;
  auto* run_cmd = app.add_subcommand("run", "run the analysis of a case file");
  run_cmd->add_option("case", case_path, "case file (YAML)")->required();
  run_cmd->add_option("-o,--output", out_dir, "output directory (default: output.dir of the case)");
  run_cmd->add_option("--threads", threads, "threads for assembly (default: all cores)");
  run_cmd->add_flag("--quiet", quiet, "no progress lines on the terminal");
  auto* check_cmd = app.add_subcommand("check", "read and validate a case and its mesh, solve nothing");
  check_cmd->add_option("case", case_path, "case file (YAML)")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 1;
  }
  if (threads > 0) omp_set_num_threads(threads);
  try {
    if (run_cmd->parsed()) return run(case_path, out_dir, quiet);
    return check(case_path);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return 3;
  }
}
