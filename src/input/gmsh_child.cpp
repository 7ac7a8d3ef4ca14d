#include "input/gmsh_child.hpp"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "core/error.hpp"
#include "core/packed_bytes.hpp"

extern char** environ;

namespace hencky::gmsh_child {
namespace {

Work& registered() {
  static Work work;
  return work;
}

// ---- The result file: what the child got, in one binary stream ----------------------------
// "HGC1", the outcome (0: the model; 1: an input error; 3: another error), its message and
// location, Gmsh's messages, then the model (core/packed_bytes.hpp).
enum Outcome : std::int64_t { model = 0, input_error = 1, other_error = 3 };
constexpr std::uint32_t magic = 0x31434748;  // "HGC1"
const char* const cut_short = "the Gmsh process's result is cut short";

void put_model(ByteWriter& w, const MshData& d) {
  w.vector(d.node_tags);
  w.vector(d.coords);
  w.value(static_cast<std::uint64_t>(d.entities.size()));
  for (const auto& e : d.entities) {
    w.value(e.dim);
    w.value(e.tag);
    w.vector(e.physicals);
  }
  w.value(static_cast<std::uint64_t>(d.blocks.size()));
  for (const auto& b : d.blocks) {
    w.value(b.dim);
    w.value(b.entity);
    w.value(b.type);
    w.vector(b.tags);
    w.vector(b.nodes);
  }
  w.value(static_cast<std::uint64_t>(d.physical_names.size()));
  for (const auto& [key, name] : d.physical_names) {
    w.value(key.first);
    w.value(key.second);
    w.string(name);
  }
  w.value(d.partitions);
  w.value(d.piece);
}

MshData get_model(ByteReader& r) {
  MshData d;
  r.vector(d.node_tags);
  r.vector(d.coords);
  d.entities.resize(r.count());
  for (auto& e : d.entities) {
    r.value(e.dim);
    r.value(e.tag);
    r.vector(e.physicals);
  }
  d.blocks.resize(r.count());
  for (auto& b : d.blocks) {
    r.value(b.dim);
    r.value(b.entity);
    r.value(b.type);
    r.vector(b.tags);
    r.vector(b.nodes);
  }
  for (std::size_t n = r.count(), k = 0; k < n; ++k) {
    int dim = 0, tag = 0;
    r.value(dim);
    r.value(tag);
    r.string(d.physical_names[{dim, tag}]);
  }
  r.value(d.partitions);
  r.value(d.piece);
  if (!r.done()) throw std::invalid_argument(cut_short);
  return d;
}

/// The error's location and message, and Gmsh's messages.
void put_report(ByteWriter& w, const SourceLocation& at, const std::string& message,
                const std::vector<std::string>& log) {
  w.string(at.file);
  w.value(at.line);
  w.value(at.column);
  w.string(at.key);
  w.string(message);
  w.strings(log);
}
void get_report(ByteReader& r, SourceLocation& at, std::string& message,
                std::vector<std::string>& log) {
  r.string(at.file);
  r.value(at.line);
  r.value(at.column);
  r.string(at.key);
  r.string(message);
  r.strings(log);
}

/// "signal 11 (Segmentation fault)".
std::string signal_text(int sig) {
  const char* name = strsignal(sig);
  return fmt::format("signal {}{}", sig, name ? fmt::format(" ({})", name) : std::string());
}

}  // namespace

void enable(Work work) {
  registered() = std::move(work);
}

bool enabled() {
  return static_cast<bool>(registered());
}

MshData run(const std::filesystem::path& file, bool geometry, int order,
            std::vector<std::string>* gmsh_log) {
  const SourceLocation where{file.string(), 0, 0, ""};
  std::error_code ec;  // TMPDIR, else /tmp
  const std::filesystem::path tmp = std::filesystem::temp_directory_path(ec);
  std::string result = ((ec ? "/tmp" : tmp) / "hencky-gmsh-XXXXXX").string();
  const int fd = mkstemp(result.data());
  if (fd < 0)
    throw InputError(where, fmt::format("cannot create a temporary file for Gmsh's result in {}: {}",
                                        result, std::strerror(errno)));
  close(fd);
  struct Remove {
    std::string path;
    ~Remove() { std::remove(path.c_str()); }
  } remove{result};
  const std::string file_arg = file.string(), geometry_arg = geometry ? "1" : "0",
                    order_arg = std::to_string(order);
  const char* exe = "/proc/self/exe";
  std::vector<char*> argv = {const_cast<char*>(exe), const_cast<char*>(marker),
                             const_cast<char*>(file_arg.c_str()), result.data(),
                             const_cast<char*>(geometry_arg.c_str()),
                             const_cast<char*>(order_arg.c_str()), nullptr};
  pid_t pid = 0;
  if (const int err = posix_spawn(&pid, exe, nullptr, nullptr, argv.data(), environ))
    throw InputError(where, fmt::format("cannot start the process that runs Gmsh: {}",
                                        std::strerror(err)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waiting for the Gmsh process failed");
  const std::string what = geometry ? "meshing this geometry" : "converting the element order";
  if (WIFSIGNALED(status))
    throw InputError(where, fmt::format(
        "Gmsh crashed ({}) while {}: a degenerate geometry (a length or an angle near zero, a "
        "surface that meets itself) is the usual cause; open the file in Gmsh (gmsh {}) to see "
        "where its meshing fails",
        signal_text(WTERMSIG(status)), what, file_arg));
  std::ifstream in(result, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::uint32_t head = 0;
  if (bytes.size() >= sizeof head) std::memcpy(&head, bytes.data(), sizeof head);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || head != magic)
    throw InputError(where, fmt::format("the process that runs Gmsh ({}) ended with status {} "
                                        "and no result",
                                        what, WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  ByteReader r(std::string_view(bytes).substr(sizeof head), cut_short);
  std::int64_t outcome = 0;
  r.value(outcome);
  SourceLocation at;
  std::string message;
  std::vector<std::string> log;
  get_report(r, at, message, log);
  if (gmsh_log) gmsh_log->insert(gmsh_log->end(), log.begin(), log.end());
  if (outcome == input_error) throw InputError(at, message);
  if (outcome != model) throw std::runtime_error(message);
  return get_model(r);
}

int child_main(int argc, char** argv) {
  if (argc != 6 || !registered()) return 2;
  // A test hook (tests/cli/cases/35_never_crash.sh): the child dies as Gmsh would on a
  // geometry it cannot handle. abort(), not a fault: the sanitizers turn faults into exit 1.
  if (const char* crash = std::getenv("HENCKY_TEST_GMSH_CHILD_ABORT"); crash && *crash == '1')
    std::abort();
  ByteWriter w;
  w.value(magic);
  std::vector<std::string> log;
  MshData data;
  std::int64_t outcome = model;
  SourceLocation at;
  std::string message;
  try {
    data = registered()(argv[2], std::string(argv[4]) == "1", std::atoi(argv[5]), &log);
  } catch (const InputError& e) {
    outcome = input_error;
    at = e.where();
    message = e.message();
  } catch (const std::exception& e) {
    outcome = other_error;
    message = e.what();
  }
  w.value(outcome);
  put_report(w, at, message, log);
  if (outcome == model) put_model(w, data);
  std::ofstream out(argv[3], std::ios::binary | std::ios::trunc);
  out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
  out.close();
  return out ? 0 : 1;
}

}  // namespace hencky::gmsh_child
