// Writing the checkpoints of a run into its output directory (CheckpointWriter, checkpoint.hpp):
// each file written whole and flushed before it is renamed into place, then the index.
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <functional>

#include "core/error.hpp"
#include "output/checkpoint.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace fs = std::filesystem;
namespace {

/// A file written whole and flushed at `tmp` becomes `path` (removed when it cannot).
void rename_into_place(const fs::path& tmp, const fs::path& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw OutputError(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
  }
}

/// Writes what `produce` hands to its sink, piece by piece, to `path` through path.tmp, flushed
/// to the disk (fsync) before the rename: the file is either the old one (or absent) or the
/// whole new one.
void write_durably(
    const fs::path& path,
    const std::function<void(const std::function<void(std::string_view)>&)>& produce) {
  const fs::path tmp = fs::path(path).concat(".tmp");
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  auto fail = [&](const char* what) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("cannot {} {}: {}", what, tmp.string(), why));
  };
  if (fd < 0) fail("create");
  produce([&](std::string_view bytes) {
    for (std::size_t at = 0; at < bytes.size();) {
      const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail("write");
      }
      at += static_cast<std::size_t>(n);
    }
  });
  if (::fsync(fd) != 0) fail("flush");
  if (::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("cannot write {}: {}", tmp.string(), why));
  }
  rename_into_place(tmp, path);
}

void write_durably(const fs::path& path, std::string_view bytes) {
  write_durably(path, [&](const std::function<void(std::string_view)>& sink) { sink(bytes); });
}

std::string file_name(int step) {
  return fmt::format("step_{:06d}.hckp", step);
}

}  // namespace

CheckpointWriter::CheckpointWriter(const Model& model, const fs::path& dir, Log& log,
                                   std::vector<CheckpointEntry> earlier,
                                   std::optional<CheckpointMesh> whole)
    : model_(model),
      dir_(dir / "checkpoints"),
      log_(log),
      whole_(std::move(whole)),
      entries_(std::move(earlier)) {
  if (!par::root()) return;
  fs::create_directories(dir_);
  if (!entries_.empty()) write_index();
}

bool CheckpointWriter::due(const StepReport& report) const {
  const int every = model_.spec().output.checkpoint_every();
  return every > 0 && report.step % every == 0;
}

void CheckpointWriter::write(const State& committed, const RunMemory& run) {
  if (model_.spec().output.checkpoint_every() == 0) return;
  const CheckpointFile f =
      checkpoint_of(model_, committed, run, whole_ ? &*whole_ : nullptr);  // collective
  const std::string name = file_name(run.steps);
  if (f.distributed()) {
    // Each rank writes its nodes' and points' values into the file itself: no rank gathers
    // the whole (docs/parallel.md). Through name.tmp, as write_durably.
    // Root's path: the output folder being written is root's (a name with its process id).
    std::string tmp = fs::path(dir_ / name).concat(".tmp").string();
    par::broadcast(tmp);
    f.write_together(tmp);  // collective
    if (!par::root()) return;
    rename_into_place(tmp, dir_ / name);
  } else {
    if (!par::root()) return;
    // Straight from the records to the file: no serialized copy (72 MB at 366k unknowns).
    write_durably(dir_ / name, [&](const auto& sink) { f.write(sink); });
  }
  std::erase_if(entries_, [&](const CheckpointEntry& e) { return e.step >= run.steps; });
  entries_.push_back({run.steps, committed.time, dir_ / name});
  ++written_;
  // The newest output.checkpoint_keep: the index first, then the files it no longer lists.
  const int keep = model_.spec().output.checkpoint_keep;
  std::vector<CheckpointEntry> dropped;
  if (keep > 0 && static_cast<int>(entries_.size()) > keep) {
    dropped.assign(entries_.begin(), entries_.end() - keep);
    entries_.erase(entries_.begin(), entries_.end() - keep);
  }
  write_index();
  for (const auto& e : dropped) {
    std::error_code ec;
    fs::remove(e.file, ec);
  }
  log_.detail("checkpoint {} (t = {:g})", name, committed.time);
}

void CheckpointWriter::write_index() const {
  std::string s = "step,time,file\n";
  for (const auto& e : entries_)
    s += fmt::format("{},{:.17g},{}\n", e.step, e.time, e.file.filename().string());
  write_durably(dir_ / "index.csv", s);
}

}  // namespace hencky
