// `hencky run` (run.hpp): the case read on every rank, the model loaded (load.hpp), the solvers
// and writers made, the analysis run, and its figures handed to summary.json (output/summary.hpp).
#include "run.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <vector>

#include "core/interrupt.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "hencky/version.hpp"
#include "input/case_reader.hpp"
#include "linalg/blas_kernels.hpp"
#include "load.hpp"
#include "output/checkpoint.hpp"
#include "output/results.hpp"
#include "output/summary.hpp"
#include "parallel/mpi.hpp"
#include "solve/analysis.hpp"
#include "solve/driver.hpp"
#include "together.hpp"

namespace hencky::cli {
namespace fs = std::filesystem;
namespace {

long peak_memory_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<long>(u.ru_maxrss) * 1024;
}

// ---- Interruption -----------------------------------------------------------------------------
// The first SIGINT or SIGTERM asks the step loop to stop (core/interrupt.hpp): it finishes the
// output and the checkpoint of the last converged step and moves the results into place (exit
// status 4). A second one stops at once (status 130): the results so far, their checkpoints
// included, stay in the work directory the message names.
char interrupt_message[4096] = "";
char abort_message[4096] = "";
std::size_t interrupt_length = 0, abort_length = 0;

extern "C" void on_signal(int) {
  if (!request_interrupt()) {
    if (interrupt_length && par::root()) [[maybe_unused]]
      auto n = ::write(STDERR_FILENO, interrupt_message, interrupt_length);
    return;
  }
  if (abort_length && par::root()) [[maybe_unused]]
    auto n = ::write(STDERR_FILENO, abort_message, abort_length);
  ::_exit(130);
}

/// Installs the handlers (after PETSc, which installs its own at its start).
void catch_interrupts(const fs::path& work_dir) {
  const std::string first =
      "\nhencky: interrupted: finishing the output and the checkpoint of the last converged step "
      "(interrupt again to stop at once)\n";
  const std::string second = fmt::format(
      "\nhencky: stopped at once; the results so far and their checkpoints are in {} (hencky "
      "run CASE --restart {} continues)\n",
      work_dir.string(), work_dir.string());
  interrupt_length = std::min(first.size(), sizeof interrupt_message);
  std::memcpy(interrupt_message, first.data(), interrupt_length);
  abort_length = std::min(second.size(), sizeof abort_message);
  std::memcpy(abort_message, second.data(), abort_length);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

/// The output directory given with -o: absolute, without a trailing separator ("out/" is
/// "out").
fs::path command_line_dir(const std::string& out_dir) {
  fs::path p = fs::absolute(out_dir).lexically_normal();
  return p.has_filename() ? p : p.parent_path();
}

/// --restart DIR [--from T]: the checkpoint to continue from, read on every rank (each its part
/// of it on a distributed mesh) and checked against the model; `earlier` gets DIR's checkpoints up
/// to it.
Restart restart_memory(const Model& model, const fs::path& dir, std::optional<double> from,
                       std::vector<CheckpointEntry>& earlier, Log& log,
                       const CheckpointMesh* whole) {
  const SourceLocation where{"", 0, 0, "--restart"};
  auto entries = list_checkpoints(dir, where);
  std::size_t pick = entries.size() - 1;  // the newest
  if (from) {
    const double eps = 1e-9 * std::max(1.0, std::abs(*from));
    auto it = std::find_if(entries.begin(), entries.end(), [&](const CheckpointEntry& e) {
      return std::abs(e.time - *from) <= eps;
    });
    // Else the one time that the list below shows as the value given (its 6 digits): what the
    // message offers can be typed back.
    const auto shown = [](double t) { return fmt::format("{:g}", t); };
    if (it == entries.end() &&
        std::count_if(entries.begin(), entries.end(),
                      [&](const CheckpointEntry& e) { return shown(e.time) == shown(*from); }) == 1)
      it = std::find_if(entries.begin(), entries.end(),
                        [&](const CheckpointEntry& e) { return shown(e.time) == shown(*from); });
    if (it == entries.end()) {
      std::string times;
      for (const auto& e : entries) times += (times.empty() ? "" : ", ") + shown(e.time);
      throw InputError(SourceLocation{"", 0, 0, "--from"},
                       fmt::format("{} has no checkpoint at t = {:g}; it has checkpoints at t = {}",
                                   dir.string(), *from, times));
    }
    pick = static_cast<std::size_t>(it - entries.begin());
  }
  const CheckpointEntry& e = entries[pick];
  // On a distributed mesh no rank reads the file whole: each reads its nodes' and points'
  // values where they are (records from 4096 numbers, 32 kB, on).
  Restart r = restore_run(
      model,
      model.part() ? CheckpointFile::read_together(e.file.string(), 4096) : read_checkpoint(e.file),
      whole);
  log.info("restart: from {} (step {}, t = {:g})", e.file.string(), r.run.steps, r.committed.time);
  entries.resize(pick + 1);
  earlier = std::move(entries);
  return r;
}

/// What a run holds, stage by stage (run() below); destroyed in the reverse order, the writers
/// before the model and the log they use.
struct Session {
  explicit Session(const RunRequest& r) : request(r) {}
  const Clock::time_point t_start = Clock::now();
  const RunRequest& request;
  Log log;
  fs::path dir;  // the output directory, from -o or output.dir
  SourceLocation dir_where;
  Loaded loaded;
  std::unique_ptr<LinearSystem> solver;
  std::unique_ptr<HeatSolver> heat;
  std::optional<Restart> resume;
  std::vector<CheckpointEntry> earlier;  // the checkpoints up to the restart's
  fs::path restart_dir;
  std::unique_ptr<ResultWriter> writer;  // root's
  std::unique_ptr<CheckpointWriter> checkpoints;
  std::optional<PieceWriter> piece;  // the other ranks'
  Timings timings;
  AnalysisResult result;
};

/// Reads the case file on every rank and finds the output directory, which root checks it can
/// write; `distribute`: whether the mesh is distributed over the ranks. Returns 0, or the exit
/// status when a rank failed (reported). Collective.
int read_run_case(Session& s, std::unique_ptr<Case>& spec, bool& distribute) {
  const RunRequest& q = s.request;
  long long case_print = 0;  // of the case file's text: the ranks must have read the same
  if (int code = together([&] {
        std::string text;  // the case file's, read once
        spec = std::make_unique<Case>(read_case(q.case_path, &text));
        s.dir = q.out_dir.empty() ? spec->output.dir : command_line_dir(q.out_dir);
        s.dir_where = q.out_dir.empty() ? spec->output.dir_where : SourceLocation{"", 0, 0, "-o"};
        // Before the mesh (Gmsh may mesh for minutes) and the analysis: root writes the
        // outputs, and can.
        if (par::root()) check_output_dir(s.dir, s.dir_where);
        // On several ranks the mesh is distributed (docs/parallel.md): root reads it and checks
        // the whole model, splits it and sends each rank its part; no rank holds the whole after.
        distribute = distributes_mesh();
        case_print = static_cast<long long>(std::hash<std::string>{}(text) >> 1);
      }))
    return code;
  // A distributed mesh is read by root alone: the ranks compare their case files instead.
  if (par::max(static_cast<int>(distribute)) != par::min(static_cast<int>(distribute)) ||
      (distribute && par::max(case_print) != par::min(case_print))) {
    if (par::root())
      std::cerr << "error: the ranks read different models (their case files differ): give "
                   "every rank the same case file and mesh\n";
    return 1;
  }
  return 0;
}

void log_model(Session& s) {
  const Loaded& loaded = s.loaded;
  s.log.info("hencky {}: {}", HENCKY_VERSION, loaded.l.spec->title);
  s.log.info("mesh: {}", loaded.mesh_line);
  if (!loaded.split_line.empty()) s.log.info("{}", loaded.split_line);
  if (!loaded.parts_line.empty()) s.log.info("{}", loaded.parts_line);
  for (const auto& line : loaded.contact_lines) s.log.info("{}", line);
}

/// The linear solvers, the memory a restart continues from, and the writers of the outputs and
/// the checkpoints. Returns 0, or the exit status when a rank failed (reported). Collective.
int prepare(Session& s) {
  LoadedCase& l = s.loaded.l;
  const Model& model = *l.model;
  const std::optional<CheckpointMesh>& whole_mesh = s.loaded.whole_mesh;
  {
    // The back ends' set-up (solver.linear: auto's factor estimate, PETSc's matrix) is setup.
    ScopedTimer timer(l.setup_seconds);
    if (int code = together([&] {
          s.solver = make_run_solver(*l.model, s.log, s.request.petsc_options);
          s.heat = make_heat_solver(*l.model, s.log, s.request.petsc_options);
        }))
      return code;
  }
  // After the solver: on several ranks it decided which integration points each rank holds.
  const std::string& restart = s.request.restart;
  s.restart_dir = restart.empty() ? fs::path() : command_line_dir(restart);
  if (int code = together([&] {
        if (!restart.empty())
          s.resume = restart_memory(model, s.restart_dir, s.request.from, s.earlier, s.log,
                                    whole_mesh ? &*whole_mesh : nullptr);
      }))
    return code;
  // Root writes every output but the other ranks' pieces of the fields files.
  if (int code = together([&] {
        if (par::root()) {
          s.writer = std::make_unique<ResultWriter>(model, s.dir, s.log, s.dir_where);
          if (s.resume)
            s.earlier = s.writer->continue_from(s.restart_dir, s.resume->run.steps, s.earlier);
        }
        if (l.spec->output.checkpoint_every() > 0)
          s.checkpoints = std::make_unique<CheckpointWriter>(
              model, s.writer ? s.writer->work_dir() : fs::path(), s.log, s.earlier, whole_mesh);
      }))
    return code;
  catch_interrupts(s.writer ? s.writer->work_dir() : fs::path());
  // The other ranks write their pieces of the fields files into root's work directory.
  std::string work_dir = s.writer ? s.writer->work_dir().string() : std::string();
  par::broadcast(work_dir);
  if (!s.writer) s.piece.emplace(model, work_dir);
  return 0;
}

void analyse(Session& s) {
  try {
    RunOptions options;
    options.resume = s.resume ? &*s.resume : nullptr;
    options.checkpoints = s.checkpoints.get();
    s.result = run_analysis(*s.loaded.l.model, *s.solver, s.log, s.timings,
                            s.writer ? static_cast<StepObserver&>(*s.writer) : *s.piece,
                            s.heat.get(), options);
  } catch (const InputError&) {
    if (s.writer) s.writer->abandon();  // bad input: nothing is overwritten or left behind
    throw;
  }
}

/// What summary.json says of the run (root's), besides the memory `f` holds already.
void gather_figures(const Session& s, int status, RunFigures& f) {
  const LoadedCase& l = s.loaded.l;
  const Model& model = *l.model;
  f.title = l.spec->title;
  f.status = status;
  if (s.resume)
    f.restart =
        RunFigures::From{s.restart_dir.string(), s.resume->run.steps, s.resume->committed.time};
  if (s.checkpoints) f.checkpoints = s.checkpoints->written();
  f.result = s.result;
  f.scheme = scheme_name(l.spec->solver.scheme);
  f.formulation = l.spec->solver.report ? "report" : "hencky";
  f.dofs = model.global_free();
  f.nodes = model.global_nodes();
  f.elements = model.global_cells();
  f.integration_points = model.total_points();
  f.threads = omp_get_max_threads();
  f.ranks = par::size();
  f.linear_solver = s.solver->stats();
  f.blas_kernels = blas_kernels().chosen;  // OpenBLAS's, after any restart
  f.warnings = s.log.warnings();
  f.mesh_seconds = l.mesh_seconds;
  f.setup_seconds = l.setup_seconds;
  f.timings = s.timings;
  if (s.heat) f.heat = RunFigures::Heat{s.heat->steps(), s.heat->iterations(), s.heat->stats()};
  f.total_seconds = seconds_since(s.t_start);
}

}  // namespace

int run(const RunRequest& request) {
  Session s(request);
  s.log.quiet = request.quiet;
  s.log.silent = !par::root();
  if (!request.threads_warning.empty()) s.log.warn(request.threads_warning);
  if (const std::string note = blas_kernels_note(); !note.empty()) s.log.detail("{}", note);
  std::unique_ptr<Case> spec;
  bool distribute = false;
  if (int code = read_run_case(s, spec, distribute)) return code;
  if (int code = load_model(std::move(spec), distribute, s.dir, s.dir_where, s.log, s.loaded))
    return code;
  log_model(s);
  if (int code = prepare(s)) return code;
  analyse(s);
  // Peak resident memory of this process and, in a parallel run, the largest and the total
  // over the ranks (collective).
  RunFigures figures;
  const long long memory = peak_memory_bytes();
  figures.peak_memory_bytes = par::max(memory);
  if (par::size() > 1) figures.peak_memory_bytes_all_ranks = par::sum(memory);
  const int status = s.result.status == AnalysisStatus::converged     ? 0
                     : s.result.status == AnalysisStatus::interrupted ? 4
                                                                      : 2;
  if (!par::root()) return status;
  gather_figures(s, status, figures);
  finish_results(*s.writer, figures, s.log);
  s.log.info("{} in {:.2f} s ({} steps, {} iterations); results in {}",
             status == 0   ? "converged"
             : status == 4 ? "interrupted"
                           : "stopped",
             seconds_since(s.t_start), s.result.steps, s.result.iterations, s.dir.string());
  // --quiet drops the progress lines, not the reason a run stopped (exit status 2 alone left
  // the user to find it in hencky.log).
  if (request.quiet && status != 0)
    std::fprintf(stderr, "stopped: %s; the converged steps are in %s\n", s.result.failure.c_str(),
                 s.dir.string().c_str());
  return status;
}

}  // namespace hencky::cli
