#pragma once
// The process group a run belongs to. hencky starts MPI (through PETSc, which initializes it)
// only when it was launched by mpirun or when the PETSc back end is asked for: a serial run with
// the direct solver never touches MPI. Every collective below is a no-op on one process, so the
// step loop calls them unconditionally.
#include <cstdint>
#include <exception>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace hencky::par {

/// The environment says this process was started by an MPI launcher (Open MPI, MPICH/Hydra or
/// PMIx).
bool launched_by_mpirun();

/// Starts MPI and PETSc now (main(), when launched by mpirun). Idempotent.
void start(int* argc, char*** argv);
/// Starts PETSc (and MPI as a singleton) if it is not running yet: the PETSc back end of a
/// serial run, and the test programs. Idempotent; finished at exit.
void ensure_petsc();
/// PETSc and MPI are running.
bool started();
/// Finalizes PETSc and MPI if hencky started them (main's last act; also run at exit).
void finish();

int rank();
int size();
inline bool root() { return rank() == 0; }

/// PETSc's text for an error code ("" when it has none).
std::string petsc_message(int code);
/// Throws std::runtime_error "PETSc: <what> failed: <PETSc's text>" when code is not 0.
void check_petsc(int code, const char* what);
/// A word of a PETSc option string that names an option ("-ksp_type"), as opposed to a value
/// ("cg", "1e-8", "-0.01").
bool is_petsc_option_name(const std::string& word);

/// Adds `options` (a PETSc option string, "-ksp_type cg -pc_type gamg") to PETSc's database.
/// Later calls override earlier ones for the same option. Throws std::invalid_argument with
/// PETSc's message when the string cannot be parsed.
void add_petsc_options(const std::string& options);

// Collectives over all ranks (no-ops on one rank).
void sum_in_place(std::span<double> v);
/// Entry by entry, the smallest (largest) over the ranks, on every rank.
void min_in_place(std::span<double> v);
void max_in_place(std::span<double> v);
long long sum(long long x);
long long max(long long x);
long long min(long long x);
int min(int x);
int max(int x);
bool any(bool x);
/// Where each rank's share of a count starts when the ranks' shares follow each other in rank
/// order: ranks + 1 entries, the first 0, entry r the sum of `mine` over the ranks before r, the
/// last the total. On every rank. Collective.
std::vector<long long> rank_offsets(long long mine);
/// Root's values to every rank.
void broadcast(std::span<int> v);
void broadcast(std::span<double> v);
void broadcast(std::string& s);
/// Point to point: `bytes` to rank `to`, and the bytes rank `from` sends (any length).
void send_bytes(int to, std::string_view bytes);
std::string receive_bytes(int from);
/// All to all: to_each[r] goes to rank r (one entry per rank); returns what each rank sent
/// here, by rank (each part below 2 GiB). Collective.
std::vector<std::string> exchange_bytes(const std::vector<std::string>& to_each);
/// Every rank's string, on root (in rank order); empty elsewhere.
std::vector<std::string> gather_strings(const std::string& s);
/// A piece of a file: `bytes` at byte `offset`.
struct FilePiece {
  std::uint64_t offset = 0;
  std::string_view bytes;
};
/// Writes one file together (the same path on every rank, on a file system they share): root
/// creates or truncates it, then each rank writes its `pieces` (none overlapping another
/// rank's) and flushes them to the disk. Returns "" or the failure's text, the same on every
/// rank. Collective.
std::string write_file_together(const std::string& path, const std::vector<FilePiece>& pieces);
/// Sum over ranks into root's `v` (other ranks' `v` unchanged).
void sum_to_root(std::span<double> v);

/// Every rank stops on an input error that one of them caught (`error`, null where none was):
/// the rank that caught it rethrows it, the others throw InputError(where, elsewhere), so that
/// root's report names the cause when root caught it. Collective; returns when none was caught.
void rethrow_anywhere(const std::exception_ptr& error, const SourceLocation& where,
                      const std::string& elsewhere);

/// The failure of the lowest rank that had one (`mine`: this rank's text, "" when none), on
/// every rank; "" when no rank failed. Collective.
std::string first_error(std::string mine);
/// Ends every rank of the run at once (MPI_Abort) with exit status `code`; on one process,
/// std::exit(code).
[[noreturn]] void abort_all(int code);

}  // namespace hencky::par
