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
#include <type_traits>

#include "core/error.hpp"

extern char** environ;

namespace hencky::gmsh_child {
namespace {

Work& registered() {
  static Work work;
  return work;
}

// ---- The result file: what the child got, in one binary stream ----------------------------
// "HGC1", the outcome (0: the model; 1: an input error; 3: another error), its message and
// location, Gmsh's messages, then the model. Written and read by the same program.
enum Outcome : std::int64_t { model = 0, input_error = 1, other_error = 3 };

struct Writer {
  std::string bytes = "HGC1";
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put(const std::string& s) {
    put(static_cast<std::int64_t>(s.size()));
    bytes.append(s);
  }
  template <class T>
  void put(const std::vector<T>& v) {
    put(static_cast<std::int64_t>(v.size()));
    if constexpr (std::is_trivially_copyable_v<T>) {
      if (!v.empty()) bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    } else {
      for (const T& x : v) put(x);
    }
  }
};

struct Reader {
  const std::string& bytes;
  std::size_t at = 4;
  void need(std::size_t n) const {
    if (n > bytes.size() - at) throw std::runtime_error("the Gmsh child's result is cut short");
  }
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof v);
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
  }
  std::size_t count() {
    std::int64_t n = 0;
    get(n);
    if (n < 0) throw std::runtime_error("the Gmsh child's result is malformed");
    return static_cast<std::size_t>(n);
  }
  void get(std::string& s) {
    const std::size_t n = count();
    need(n);
    s.assign(bytes, at, n);
    at += n;
  }
  template <class T>
  void get(std::vector<T>& v) {
    const std::size_t n = count();
    if constexpr (std::is_trivially_copyable_v<T>) {
      if (n > (bytes.size() - at) / sizeof(T))
        throw std::runtime_error("the Gmsh child's result is cut short");
      v.resize(n);
      if (n > 0) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));  // data() may be null
      at += n * sizeof(T);
    } else {
      v.clear();
      for (std::size_t k = 0; k < n; ++k) get(v.emplace_back());
    }
  }
};

void put_model(Writer& w, const MshData& d) {
  w.put(d.node_tags);
  w.put(d.coords);
  w.put(static_cast<std::int64_t>(d.entities.size()));
  for (const auto& e : d.entities) {
    w.put(e.dim);
    w.put(e.tag);
    w.put(e.physicals);
  }
  w.put(static_cast<std::int64_t>(d.blocks.size()));
  for (const auto& b : d.blocks) {
    w.put(b.dim);
    w.put(b.entity);
    w.put(b.type);
    w.put(b.tags);
    w.put(b.nodes);
  }
  w.put(static_cast<std::int64_t>(d.physical_names.size()));
  for (const auto& [key, name] : d.physical_names) {
    w.put(key.first);
    w.put(key.second);
    w.put(name);
  }
  w.put(d.partitions);
  w.put(d.piece);
}

MshData get_model(Reader& r) {
  MshData d;
  r.get(d.node_tags);
  r.get(d.coords);
  d.entities.resize(r.count());
  for (auto& e : d.entities) {
    r.get(e.dim);
    r.get(e.tag);
    r.get(e.physicals);
  }
  for (std::size_t n = r.count(), k = 0; k < n; ++k) {
    auto& b = d.blocks.emplace_back();
    r.get(b.dim);
    r.get(b.entity);
    r.get(b.type);
    r.get(b.tags);
    r.get(b.nodes);
  }
  for (std::size_t n = r.count(), k = 0; k < n; ++k) {
    int dim = 0, tag = 0;
    r.get(dim);
    r.get(tag);
    r.get(d.physical_names[{dim, tag}]);
  }
  r.get(d.partitions);
  r.get(d.piece);
  return d;
}

/// The error's location and message, and Gmsh's messages.
void put_report(Writer& w, const SourceLocation& at, const std::string& message,
                const std::vector<std::string>& log) {
  w.put(at.file);
  w.put(at.line);
  w.put(at.column);
  w.put(at.key);
  w.put(message);
  w.put(log);
}
void get_report(Reader& r, SourceLocation& at, std::string& message,
                std::vector<std::string>& log) {
  r.get(at.file);
  r.get(at.line);
  r.get(at.column);
  r.get(at.key);
  r.get(message);
  r.get(log);
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
  const char* tmp = std::getenv("TMPDIR");
  std::string result = (tmp && *tmp ? std::string(tmp) : std::string("/tmp")) +
                       "/hencky-gmsh-XXXXXX";
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
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.compare(0, 4, "HGC1") != 0)
    throw InputError(where, fmt::format("the process that runs Gmsh ({}) ended with status {} "
                                        "and no result",
                                        what, WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  Reader r{bytes};
  std::int64_t outcome = 0;
  r.get(outcome);
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
  Writer w;
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
  w.put(outcome);
  put_report(w, at, message, log);
  if (outcome == model) put_model(w, data);
  std::ofstream out(argv[3], std::ios::binary | std::ios::trunc);
  out.write(w.bytes.data(), static_cast<std::streamsize>(w.bytes.size()));
  out.close();
  return out ? 0 : 1;
}

}  // namespace hencky::gmsh_child
