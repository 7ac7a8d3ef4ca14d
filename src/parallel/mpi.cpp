#include "parallel/mpi.hpp"

#include <fcntl.h>
#include <petscsys.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace hencky::par {
namespace {

bool petsc_started = false;
bool finished = false;

bool running() { return petsc_started && !finished; }

void start_petsc() {
  if (petsc_started) return;
  // hencky reads its own command line (PETSc options from it are added by the caller) and keeps
  // the default signal handling, so that a crash is a crash (and the sanitizers see it).
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  check_petsc(PetscInitializeNoArguments(), "initialization");
  // Errors come back as codes and become exceptions (petsc_solver.cpp) instead of PETSc's
  // printed traceback.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  petsc_started = true;
  std::atexit(finish);
}

MPI_Comm comm() { return PETSC_COMM_WORLD; }

}  // namespace

std::string petsc_message(int code) {
  // PETSc's text for the code, and its specific message of the error just raised (which says
  // what failed: the generic text alone can be empty).
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(static_cast<PetscErrorCode>(code), &text, &specific);
  std::string m = text ? text : "";
  if (specific && *specific) m += (m.empty() ? "" : ": ") + std::string(specific);
  while (!m.empty() && std::isspace(static_cast<unsigned char>(m.back()))) m.pop_back();
  return m.empty() ? "PETSc error " + std::to_string(code) : m;
}

void check_petsc(int code, const char* what) {
  if (code != 0)
    throw std::runtime_error(std::string("PETSc: ") + what + " failed: " + petsc_message(code));
}

bool is_petsc_option_name(const std::string& word) {
  return word.size() > 1 && word[0] == '-' &&
         !std::isdigit(static_cast<unsigned char>(word[1])) && word[1] != '.';
}

bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

void start(int*, char***) { start_petsc(); }
void ensure_petsc() { start_petsc(); }
bool started() { return running(); }

void finish() {
  if (!running()) return;
  finished = true;
  PetscFinalize();
}

int rank() {
  if (!running()) return 0;
  int r = 0;
  MPI_Comm_rank(comm(), &r);
  return r;
}

int size() {
  if (!running()) return 1;
  int s = 1;
  MPI_Comm_size(comm(), &s);
  return s;
}

void add_petsc_options(const std::string& options) {
  if (options.empty()) return;
  ensure_petsc();
  if (const PetscErrorCode code = PetscOptionsInsertString(nullptr, options.c_str()))
    throw std::invalid_argument("PETSc cannot read the options \"" + options +
                                "\": " + petsc_message(code));
}

namespace {
template <class T>
void reduce_in_place(std::span<T> v, MPI_Datatype type, MPI_Op op) {
  if (size() > 1)
    MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), type, op, comm());
}
template <class T>
T reduce(T x, MPI_Datatype type, MPI_Op op) {
  reduce_in_place(std::span<T>(&x, 1), type, op);
  return x;
}
}  // namespace

void sum_in_place(std::span<double> v) { reduce_in_place(v, MPI_DOUBLE, MPI_SUM); }
void min_in_place(std::span<double> v) { reduce_in_place(v, MPI_DOUBLE, MPI_MIN); }
void max_in_place(std::span<double> v) { reduce_in_place(v, MPI_DOUBLE, MPI_MAX); }

long long sum(long long x) { return reduce(x, MPI_LONG_LONG, MPI_SUM); }
long long max(long long x) { return reduce(x, MPI_LONG_LONG, MPI_MAX); }
long long min(long long x) { return reduce(x, MPI_LONG_LONG, MPI_MIN); }
int min(int x) { return reduce(x, MPI_INT, MPI_MIN); }
int max(int x) { return reduce(x, MPI_INT, MPI_MAX); }
bool any(bool x) { return reduce(x ? 1 : 0, MPI_INT, MPI_MAX) != 0; }

void broadcast(std::span<int> v) {
  if (size() > 1) MPI_Bcast(v.data(), static_cast<int>(v.size()), MPI_INT, 0, comm());
}
void broadcast(std::span<double> v) {
  if (size() > 1) MPI_Bcast(v.data(), static_cast<int>(v.size()), MPI_DOUBLE, 0, comm());
}

void broadcast(std::string& s) {
  if (size() == 1) return;
  int n = static_cast<int>(s.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm());
  s.resize(static_cast<std::size_t>(n));
  MPI_Bcast(s.data(), n, MPI_CHAR, 0, comm());
}

// In chunks of at most 1 GiB: MPI counts are ints.
constexpr std::size_t chunk = std::size_t{1} << 30;

void send_bytes(int to, std::string_view bytes) {
  unsigned long long n = bytes.size();
  MPI_Send(&n, 1, MPI_UNSIGNED_LONG_LONG, to, 0, comm());
  for (std::size_t at = 0; at < bytes.size(); at += chunk)
    MPI_Send(bytes.data() + at, static_cast<int>(std::min(chunk, bytes.size() - at)), MPI_CHAR, to,
             0, comm());
}

std::string receive_bytes(int from) {
  unsigned long long n = 0;
  MPI_Recv(&n, 1, MPI_UNSIGNED_LONG_LONG, from, 0, comm(), MPI_STATUS_IGNORE);
  std::string bytes(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += chunk)
    MPI_Recv(bytes.data() + at, static_cast<int>(std::min<std::size_t>(chunk, n - at)), MPI_CHAR,
             from, 0, comm(), MPI_STATUS_IGNORE);
  return bytes;
}

std::vector<long long> rank_offsets(long long mine) {
  const int p = size();
  std::vector<long long> all(p, mine), out(p + 1, 0);
  if (p > 1) MPI_Allgather(&mine, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, comm());
  for (int r = 0; r < p; ++r) out[r + 1] = out[r] + all[r];
  return out;
}

std::vector<std::string> exchange_bytes(const std::vector<std::string>& to_each) {
  const int p = size();
  if (static_cast<int>(to_each.size()) != p)
    throw std::invalid_argument("exchange_bytes: one entry per rank");
  if (p == 1) return to_each;
  std::vector<int> send_n(p), recv_n(p), send_at(p, 0), recv_at(p, 0);
  long long out_total = 0, in_total = 0;
  for (int r = 0; r < p; ++r) {
    send_n[r] = static_cast<int>(std::min<std::size_t>(to_each[r].size(), INT_MAX));
    out_total += static_cast<long long>(to_each[r].size());
  }
  MPI_Alltoall(send_n.data(), 1, MPI_INT, recv_n.data(), 1, MPI_INT, comm());
  for (int r = 0; r < p; ++r) in_total += recv_n[r];
  // MPI's counts and offsets are ints: every rank refuses together.
  if (any(out_total > INT_MAX || in_total > INT_MAX))
    throw std::invalid_argument("exchange_bytes: 2 GiB or more from or to one rank");
  std::string out_all, in_all(static_cast<std::size_t>(in_total), '\0');
  out_all.reserve(static_cast<std::size_t>(out_total));
  for (int r = 0; r < p; ++r) {
    send_at[r] = static_cast<int>(out_all.size());
    out_all += to_each[r];
  }
  for (int r = 1; r < p; ++r) recv_at[r] = recv_at[r - 1] + recv_n[r - 1];
  MPI_Alltoallv(out_all.data(), send_n.data(), send_at.data(), MPI_CHAR, in_all.data(),
                recv_n.data(), recv_at.data(), MPI_CHAR, comm());
  std::vector<std::string> out(p);
  for (int r = 0; r < p; ++r) out[r] = in_all.substr(recv_at[r], recv_n[r]);
  return out;
}

std::vector<std::string> gather_strings(const std::string& s) {
  if (size() == 1) return {s};
  const int p = size();
  int n = static_cast<int>(s.size());
  std::vector<int> lengths(p), offsets(p, 0);
  MPI_Gather(&n, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm());
  int total = 0;
  for (int r = 0; r < p; ++r) offsets[r] = total, total += lengths[r];
  std::string all(root() ? static_cast<std::size_t>(total) : 0, '\0');
  MPI_Gatherv(s.data(), n, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              comm());
  std::vector<std::string> out;
  if (root())
    for (int r = 0; r < p; ++r) out.push_back(all.substr(offsets[r], lengths[r]));
  return out;
}

std::string write_file_together(const std::string& path, const std::vector<FilePiece>& pieces) {
  // Plain POSIX writes at offsets (pwrite), each rank its own pieces, after root created the
  // file: MPI-IO would do the same, but Open MPI 4.1's OMPIO deadlocks in its shared-file-
  // pointer component when that fails to start on one rank (seen as root, in MPI_File_open).
  // On a shared network file system the ranks' writes are disjoint byte ranges, flushed and
  // closed before root reads the file back (close-to-open consistency).
  std::string error;
  if (root()) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0 || ::close(fd) != 0) error = std::strerror(errno);
  }
  if (any(!error.empty())) {  // root's failure
    broadcast(error);
    return error;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) error = std::strerror(errno);
  for (std::size_t k = 0; fd >= 0 && error.empty() && k < pieces.size(); ++k) {
    const std::string_view b = pieces[k].bytes;
    for (std::size_t done = 0; done < b.size();) {
      const ssize_t n = ::pwrite(fd, b.data() + done, b.size() - done,
                                 static_cast<off_t>(pieces[k].offset + done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        error = std::strerror(errno);
        break;
      }
      done += static_cast<std::size_t>(n);
    }
  }
  if (fd >= 0 && ::fsync(fd) != 0 && error.empty()) error = std::strerror(errno);
  if (fd >= 0 && ::close(fd) != 0 && error.empty()) error = std::strerror(errno);
  return first_error(error);
}

std::string first_error(std::string mine) {
  const int first = min(mine.empty() ? INT_MAX : rank());
  if (first == INT_MAX) return "";
  if (first != 0) {
    if (rank() == first) send_bytes(0, mine);
    if (root()) mine = receive_bytes(first);
  }
  broadcast(mine);
  return mine;
}

void sum_to_root(std::span<double> v) {
  if (size() == 1) return;
  const int n = static_cast<int>(v.size());
  if (root())
    MPI_Reduce(MPI_IN_PLACE, v.data(), n, MPI_DOUBLE, MPI_SUM, 0, comm());
  else
    MPI_Reduce(v.data(), nullptr, n, MPI_DOUBLE, MPI_SUM, 0, comm());
}

void abort_all(int code) {
  if (size() > 1) MPI_Abort(comm(), code);
  std::exit(code);
}

void rethrow_anywhere(const std::exception_ptr& error, const SourceLocation& where,
                      const std::string& elsewhere) {
  if (!any(error != nullptr)) return;
  if (error) std::rethrow_exception(error);
  throw InputError(where, elsewhere);
}

}  // namespace hencky::par
