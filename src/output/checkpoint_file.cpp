// The checkpoint container (checkpoint_file.hpp): writing, and a reader that trusts nothing.
#include "output/checkpoint_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <climits>
#include <cstring>
#include <optional>

#include "core/error.hpp"
#include "core/invariant.hpp"
#include "parallel/mpi.hpp"

static_assert(std::endian::native == std::endian::little,
              "the checkpoint format is little-endian; a big-endian build needs byte swaps");

namespace hencky {
namespace {

constexpr char magic[8] = {'H', 'N', 'C', 'K', 'C', 'K', 'P', 'T'};
constexpr std::size_t header_size = 32;
constexpr std::size_t max_name = 255;

std::array<std::uint32_t, 256> crc_table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

template <class T>
void append(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

template <class T>
T take(std::string_view bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

std::size_t value_size(CheckpointFile::Type t) {
  switch (t) {
    case CheckpointFile::Type::f64:
    case CheckpointFile::Type::i64:
      return 8;
    case CheckpointFile::Type::u8:
    case CheckpointFile::Type::text:
      return 1;
  }
  return 0;
}

const char* type_name(CheckpointFile::Type t) {
  switch (t) {
    case CheckpointFile::Type::f64:
      return "float64";
    case CheckpointFile::Type::i64:
      return "int64";
    case CheckpointFile::Type::u8:
      return "uint8";
    case CheckpointFile::Type::text:
      return "text";
  }
  return "?";
}

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
  static const auto table = crc_table();
  std::uint32_t c = crc ^ 0xFFFFFFFFu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void CheckpointFile::put(const std::string& name, std::span<const double> v) {
  Record r;
  r.type = Type::f64;
  r.f64.assign(v.begin(), v.end());
  records_[name] = std::move(r);
}
void CheckpointFile::put(const std::string& name, std::span<const std::int64_t> v) {
  Record r;
  r.type = Type::i64;
  r.i64.assign(v.begin(), v.end());
  records_[name] = std::move(r);
}
void CheckpointFile::put(const std::string& name, std::span<const std::uint8_t> v) {
  Record r;
  r.type = Type::u8;
  r.u8.assign(v.begin(), v.end());
  records_[name] = std::move(r);
}
void CheckpointFile::put(const std::string& name, std::string text) {
  Record r;
  r.type = Type::text;
  r.text = std::move(text);
  records_[name] = std::move(r);
}

namespace {
/// A record's head in the file: its name's length, its name, its type and its count.
std::string head_of(const std::string& name, const CheckpointFile::Record& r) {
  std::string head;
  append<std::uint32_t>(head, static_cast<std::uint32_t>(name.size()));
  head += name;
  append<std::uint8_t>(head, static_cast<std::uint8_t>(r.type));
  append<std::uint64_t>(head, r.count());
  return head;
}

/// The bytes of a record's values held in memory (a distributed record's: this rank's runs).
std::string_view values_of(const CheckpointFile::Record& r) {
  switch (r.type) {
    case CheckpointFile::Type::f64:
      return {reinterpret_cast<const char*>(r.f64.data()), 8 * r.f64.size()};
    case CheckpointFile::Type::i64:
      return {reinterpret_cast<const char*>(r.i64.data()), 8 * r.i64.size()};
    case CheckpointFile::Type::u8:
      return {reinterpret_cast<const char*>(r.u8.data()), r.u8.size()};
    case CheckpointFile::Type::text:
      return r.text;
  }
  return {};
}

/// Reads `n` bytes at `at` of an open file into `out`; false on a read error or a short file.
bool read_at(int fd, std::uint64_t at, std::size_t n, char* out) {
  for (std::size_t done = 0; done < n;) {
    const ssize_t k = ::pread(fd, out + done, n - done, static_cast<off_t>(at + done));
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    done += static_cast<std::size_t>(k);
  }
  return true;
}

/// The CRC-32 of an open file's bytes from `from` to `end`, read in pieces of 4 MiB; nullopt on
/// a read error.
std::optional<std::uint32_t> crc_of_file(int fd, std::uint64_t from, std::uint64_t end) {
  std::string chunk(std::size_t{4} << 20, '\0');
  std::uint32_t crc = 0;
  for (std::uint64_t at = from; at < end;) {
    const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(chunk.size(), end - at));
    if (!read_at(fd, at, n, chunk.data())) return std::nullopt;
    crc = crc32(std::string_view(chunk.data(), n), crc);
    at += n;
  }
  return crc;
}
}  // namespace

void CheckpointFile::put_runs(const std::string& name, std::uint64_t total,
                              std::vector<long long> start, std::vector<int> length,
                              std::vector<double> values) {
  if (par::size() == 1) {
    std::vector<double> whole(total, 0.0);
    for (std::size_t i = 0, at = 0; i < start.size(); at += length[i++])
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(at), length[i],
                  whole.begin() + start[i]);
    return put(name, std::span<const double>(whole));
  }
  Record r;
  r.type = Type::f64;
  r.runs = true;
  r.total = total;
  r.run_start = std::move(start);
  r.run_length = std::move(length);
  r.f64 = std::move(values);
  records_[name] = std::move(r);
}

bool CheckpointFile::distributed() const {
  return std::any_of(records_.begin(), records_.end(),
                     [](const auto& named) { return named.second.runs; });
}

void CheckpointFile::write_together(const std::string& path) const {
  // Root lays the file out: its own bytes (the header, every record's head, the values of the
  // records it holds whole) and where each distributed record's values begin.
  std::vector<std::pair<std::uint64_t, std::string>> own;
  std::vector<par::FilePiece> pieces;
  std::string value_at;  // uint64 offsets, one per distributed record, in record order
  if (par::root()) {
    std::uint64_t at = header_size;
    for (const auto& [name, r] : records_) {
      own.emplace_back(at, head_of(name, r));
      at += own.back().second.size();
      const std::string_view values = values_of(r);
      if (r.runs) {
        append<std::uint64_t>(value_at, at);
        at += 8 * r.total;
      } else {
        pieces.push_back({at, values});
        at += values.size();
      }
    }
    std::string header(magic, sizeof magic);
    append<std::uint32_t>(header, checkpoint_format_version);
    append<std::uint32_t>(header, 0);
    append<std::uint64_t>(header, at - header_size);
    append<std::uint32_t>(header, 0);  // the checksum, once the file is whole
    append<std::uint32_t>(header, 0);
    own.emplace_back(0, std::move(header));
    for (const auto& [offset, bytes] : own) pieces.push_back({offset, bytes});
  }
  par::broadcast(value_at);
  std::size_t k = 0;
  for (const auto& [name, r] : records_) {
    if (!r.runs) continue;
    HENCKY_VERIFY(8 * (k + 1) <= value_at.size(),
                  "CheckpointFile::write_together: the ranks' records differ");
    const auto first = take<std::uint64_t>(value_at, 8 * k++);
    for (std::size_t i = 0, from = 0; i < r.run_start.size(); from += r.run_length[i++])
      pieces.push_back({first + 8 * static_cast<std::uint64_t>(r.run_start[i]),
                        {reinterpret_cast<const char*>(r.f64.data() + from),
                         8 * static_cast<std::size_t>(r.run_length[i])}});
  }
  HENCKY_VERIFY(8 * k == value_at.size(),
                "CheckpointFile::write_together: the ranks' records differ");
  std::sort(pieces.begin(), pieces.end(),
            [](const par::FilePiece& a, const par::FilePiece& b) { return a.offset < b.offset; });
  if (const std::string error = par::write_file_together(path, pieces); !error.empty())
    throw OutputError(fmt::format("cannot write {}: {}", path, error));
  if (!par::root()) return;
  // The checksum of the payload, read back in pieces of 4 MiB, into the header; then the file
  // to the disk.
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  auto fail = [&](const char* what) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    throw OutputError(fmt::format("cannot {} {}: {}", what, path, why));
  };
  if (fd < 0) fail("open");
  struct stat st {};
  if (::fstat(fd, &st) != 0) fail("read back");
  const auto crc = crc_of_file(fd, header_size, static_cast<std::uint64_t>(st.st_size));
  if (!crc) fail("read back");
  if (::pwrite(fd, &*crc, sizeof *crc, 24) != static_cast<ssize_t>(sizeof *crc)) fail("write");
  if (::fsync(fd) != 0) fail("flush");
  if (::close(fd) != 0)
    throw OutputError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
}

std::size_t CheckpointFile::Record::count() const {
  if (runs) return total;
  if (in_file) return file_count;
  switch (type) {
    case Type::f64:
      return f64.size();
    case Type::i64:
      return i64.size();
    case Type::u8:
      return u8.size();
    case Type::text:
      return text.size();
  }
  return 0;
}

const CheckpointFile::Record& CheckpointFile::get(const std::string& name, Type type,
                                                  long long expected) const {
  const auto it = records_.find(name);
  const SourceLocation where{label_, 0, 0, ""};
  if (it == records_.end())
    throw InputError(where, fmt::format("the checkpoint has no record '{}' (not written by this "
                                        "version of hencky, or damaged)",
                                        name));
  const Record& r = it->second;
  if (r.type != type)
    throw InputError(where, fmt::format("checkpoint record '{}' holds {} values, expected {}", name,
                                        type_name(r.type), type_name(type)));
  if (expected >= 0 && r.count() != static_cast<std::size_t>(expected))
    throw InputError(where, fmt::format("checkpoint record '{}' has {} values, expected {} (a "
                                        "checkpoint of another model?)",
                                        name, r.count(), expected));
  return r;
}

const std::vector<double>& CheckpointFile::f64(const std::string& name, long long expected) const {
  const Record& r = get(name, Type::f64, expected);
  if (r.in_file && r.f64.size() != r.file_count) {  // read whole on first use
    std::vector<double> all(r.file_count);
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    const bool ok =
        fd >= 0 && read_at(fd, r.file_offset, 8 * all.size(), reinterpret_cast<char*>(all.data()));
    if (fd >= 0) ::close(fd);
    if (!ok)
      throw InputError(SourceLocation{label_, 0, 0, name},
                       "cannot read the checkpoint (a read failed or came up short)");
    r.f64 = std::move(all);
  }
  return r.f64;
}
const std::vector<std::int64_t>& CheckpointFile::i64(const std::string& name,
                                                     long long expected) const {
  return get(name, Type::i64, expected).i64;
}
const std::vector<std::uint8_t>& CheckpointFile::u8(const std::string& name,
                                                    long long expected) const {
  return get(name, Type::u8, expected).u8;
}
const std::string& CheckpointFile::text(const std::string& name) const {
  return get(name, Type::text, -1).text;
}

void CheckpointFile::payload(const std::function<void(std::string_view)>& piece) const {
  for (const auto& [name, r] : records_) {
    piece(head_of(name, r));
    piece(values_of(r));
  }
}

void CheckpointFile::write(const std::function<void(std::string_view)>& sink) const {
  HENCKY_VERIFY(!distributed(), "CheckpointFile::write: a distributed record needs write_together");
  // Two passes over the records: the size and the checksum for the header, then the bytes.
  std::uint64_t size = 0;
  std::uint32_t crc = 0;
  payload([&](std::string_view p) {
    size += p.size();
    crc = crc32(p, crc);
  });
  std::string header(magic, sizeof magic);
  append<std::uint32_t>(header, checkpoint_format_version);
  append<std::uint32_t>(header, 0);
  append<std::uint64_t>(header, size);
  append<std::uint32_t>(header, crc);
  append<std::uint32_t>(header, 0);
  sink(header);
  payload([&](std::string_view p) {
    if (!p.empty()) sink(p);
  });
}

std::string CheckpointFile::serialize() const {
  std::string out;
  write([&](std::string_view p) { out += p; });
  return out;
}

/// Where a checkpoint's bytes come from: `total` bytes, `fetch(at, n)` the n bytes at `at`
/// (valid until the next call), `crc_from(at)` the CRC-32 of the bytes from `at` to the end
/// (nullopt: not checked here).
struct CheckpointFile::Source {
  std::uint64_t total = 0;
  std::function<std::string_view(std::uint64_t, std::size_t)> fetch;
  std::function<std::optional<std::uint32_t>(std::uint64_t)> crc_from;
};

CheckpointFile CheckpointFile::parse(std::string_view bytes, const std::string& label) {
  Source src;
  src.total = bytes.size();
  src.fetch = [&](std::uint64_t at, std::size_t n) { return bytes.substr(at, n); };
  src.crc_from = [&](std::uint64_t at) -> std::optional<std::uint32_t> {
    return crc32(bytes.substr(at));
  };
  return parse_from(src, label, UINT64_MAX);
}

CheckpointFile CheckpointFile::parse_from(const Source& src, const std::string& label,
                                          std::uint64_t in_file_from) {
  const SourceLocation where{label, 0, 0, ""};
  auto fail = [&](const std::string& why) { return InputError(where, why); };
  const std::string_view bytes = src.fetch(0, std::min<std::uint64_t>(src.total, header_size));
  if (bytes.size() < header_size || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    throw fail("not a hencky checkpoint (its first bytes are not \"HNCKCKPT\")");
  const auto version = take<std::uint32_t>(bytes, 8);
  if (version > checkpoint_format_version)
    throw fail(fmt::format(
        "the checkpoint is of format version {}, written by a newer hencky; this hencky reads "
        "version {}: restart with the hencky that wrote it",
        version, checkpoint_format_version));
  if (version == 0) throw fail("the checkpoint's format version is 0: the file is damaged");
  const auto size = take<std::uint64_t>(bytes, 16);
  if (size != src.total - header_size)
    throw fail(
        fmt::format("the checkpoint is truncated or damaged: its header announces {} "
                    "bytes of data, the file has {}",
                    size, src.total - header_size));
  const auto crc = take<std::uint32_t>(bytes, 24);
  if (const auto found = src.crc_from(header_size); found && *found != crc)
    throw fail("the checkpoint is damaged: its checksum (CRC-32) does not match its data");
  CheckpointFile f;
  f.label_ = label;
  const std::uint64_t end = src.total - header_size;  // the payload's bytes
  std::uint64_t at = 0;                               // in the payload
  auto need = [&](std::uint64_t n, const char* what) {
    if (n > end - at)
      throw fail(fmt::format("the checkpoint is damaged: {} at byte {} runs past its end", what,
                             header_size + at));
  };
  auto fetch = [&](std::uint64_t n) { return src.fetch(header_size + at, n); };
  while (at < end) {
    need(4, "a record's name length");
    const auto name_size = take<std::uint32_t>(fetch(4), 0);
    at += 4;
    if (name_size == 0 || name_size > max_name)
      throw fail(fmt::format("the checkpoint is damaged: a record name of {} bytes at byte {}",
                             name_size, header_size + at - 4));
    need(name_size + 1 + 8, "a record's header");
    const std::string_view head = fetch(name_size + 1 + 8);
    std::string name(head.substr(0, name_size));
    at += name_size;
    const auto type = static_cast<Type>(take<std::uint8_t>(head, name_size));
    at += 1;
    if (value_size(type) == 0)
      throw fail(fmt::format("the checkpoint is damaged: record '{}' has an unknown type {}", name,
                             static_cast<int>(type)));
    const auto count = take<std::uint64_t>(head, name_size + 1);
    at += 8;
    if (count > (end - at) / value_size(type))
      throw fail(
          fmt::format("the checkpoint is damaged: record '{}' announces {} values, more "
                      "than the file holds",
                      name, count));
    if (f.records_.count(name))
      throw fail(fmt::format("the checkpoint is damaged: record '{}' appears twice", name));
    Record r;
    r.type = type;
    if (type == Type::f64 && count >= in_file_from) {
      r.in_file = true;
      r.file_offset = header_size + at;
      r.file_count = count;
    } else {
      const std::string_view values = fetch(count * value_size(type));
      const char* p = values.data();
      switch (type) {
        case Type::f64:
          r.f64.resize(count);
          if (count) std::memcpy(r.f64.data(), p, 8 * count);
          break;
        case Type::i64:
          r.i64.resize(count);
          if (count) std::memcpy(r.i64.data(), p, 8 * count);
          break;
        case Type::u8:
          r.u8.assign(p, p + count);
          break;
        case Type::text:
          r.text.assign(p, count);
          break;
      }
    }
    at += count * value_size(type);
    f.records_.emplace(std::move(name), std::move(r));
  }
  return f;
}

CheckpointFile CheckpointFile::read_together(const std::string& path, std::uint64_t in_file_from) {
  const SourceLocation where{path, 0, 0, ""};
  std::string error;
  CheckpointFile f;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  try {
    struct stat st {};
    if (fd < 0 || ::fstat(fd, &st) != 0)
      throw InputError(where, fmt::format("cannot read the checkpoint: {}", std::strerror(errno)));
    std::string buffer;
    Source src;
    src.total = static_cast<std::uint64_t>(st.st_size);
    src.fetch = [&](std::uint64_t at, std::size_t n) {
      buffer.resize(n);
      if (!read_at(fd, at, n, buffer.data()))
        throw InputError(where, "cannot read the checkpoint (a read failed or came up short)");
      return std::string_view(buffer);
    };
    // Root checks the checksum, reading the file in pieces; the others trust it.
    src.crc_from = [&](std::uint64_t at) -> std::optional<std::uint32_t> {
      if (!par::root()) return std::nullopt;
      const auto crc = crc_of_file(fd, at, src.total);
      if (!crc) throw InputError(where, "cannot read the checkpoint (a read failed)");
      return crc;
    };
    f = parse_from(src, path, in_file_from);
    f.path_ = path;
  } catch (const InputError& e) {
    error = e.message();
  }
  if (fd >= 0) ::close(fd);
  // Root's verdict first (the checksum is its alone), then the lowest rank that failed.
  error = par::first_error(std::move(error));
  if (error.empty()) return f;
  throw InputError(where, error);
}

std::vector<double> CheckpointFile::f64_runs(const std::string& name, long long expected,
                                             std::span<const long long> start,
                                             std::span<const int> length) const {
  const Record& r = get(name, Type::f64, expected);
  std::size_t n = 0;
  for (int l : length) n += static_cast<std::size_t>(l);
  std::vector<double> out(n);
  const SourceLocation where{label_, 0, 0, name};
  for (std::size_t i = 0; i < start.size(); ++i)
    if (start[i] < 0 || static_cast<std::uint64_t>(start[i]) + length[i] > r.count())
      throw std::out_of_range("CheckpointFile::f64_runs: a run outside record " + name);
  if (!r.in_file) {
    for (std::size_t i = 0, at = 0; i < start.size(); at += length[i++])
      std::copy_n(r.f64.begin() + start[i], length[i],
                  out.begin() + static_cast<std::ptrdiff_t>(at));
    return out;
  }
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  bool ok = fd >= 0;
  // Neighbouring runs are read at once.
  for (std::size_t i = 0, at = 0; ok && i < start.size();) {
    std::size_t j = i + 1, values = static_cast<std::size_t>(length[i]);
    while (j < start.size() && start[j] == start[j - 1] + length[j - 1])
      values += static_cast<std::size_t>(length[j++]);
    ok = read_at(fd, r.file_offset + 8 * static_cast<std::uint64_t>(start[i]), 8 * values,
                 reinterpret_cast<char*>(out.data() + at));
    at += values;
    i = j;
  }
  if (fd >= 0) ::close(fd);
  if (!ok) throw InputError(where, "cannot read the checkpoint (a read failed or came up short)");
  return out;
}

}  // namespace hencky
