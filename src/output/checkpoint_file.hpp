#pragma once
// The container of a checkpoint (docs/outputs.md, "Checkpoints"): a flat list of named arrays
// behind a header with a format version and a CRC-32 of everything after the header.
//
//   offset  size  content
//        0     8  magic "HNCKCKPT"
//        8     4  format version (uint32; this hencky writes and reads 1)
//       12     4  0 (reserved)
//       16     8  payload size in bytes (uint64)
//       24     4  CRC-32 (IEEE 802.3, as zlib's crc32) of the payload
//       28     4  0 (reserved)
//       32     -  payload: records, each
//                   uint32 name length, the name (UTF-8, at most 255 bytes),
//                   uint8 type (1 float64, 2 int64, 3 uint8, 4 text), uint64 count,
//                   count values (8, 8, 1, 1 bytes each)
// All numbers are little-endian. The reader checks the header, the size and the checksum
// before it looks at a record, and every count against the bytes that are left: a truncated,
// corrupted or foreign file is an InputError naming it, never a crash.
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hencky {

inline constexpr std::uint32_t checkpoint_format_version = 1;

/// CRC-32 (IEEE, reflected polynomial 0xEDB88320), as zlib's crc32 and `cksum -a crc32b`.
/// Continues from `crc`, the CRC of the bytes before: crc32(b, crc32(a)) == crc32(a + b).
std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

class CheckpointFile {
 public:
  enum class Type : std::uint8_t { f64 = 1, i64 = 2, u8 = 3, text = 4 };
  struct Record {
    Type type = Type::f64;
    mutable std::vector<double> f64;  ///< (an in-file record's, once f64() read it)
    std::vector<std::int64_t> i64;
    std::vector<std::uint8_t> u8;
    std::string text;
    /// A distributed record (put_runs): its whole length, and this rank's runs of it (their
    /// values in f64).
    /// A record read_together left in the file: where its values start, and how many.
    bool in_file = false;
    std::uint64_t file_offset = 0, file_count = 0;
    bool runs = false;
    std::uint64_t total = 0;
    std::vector<long long> run_start;
    std::vector<int> run_length;
    std::size_t count() const;  ///< values of its type
  };

  void put(const std::string& name, std::span<const double> v);
  void put(const std::string& name, std::span<const std::int64_t> v);
  void put(const std::string& name, std::span<const std::uint8_t> v);
  void put(const std::string& name, std::string text);
  void put(const std::string& name, double v) { put(name, std::span<const double>(&v, 1)); }
  void put(const std::string& name, std::int64_t v) {
    put(name, std::span<const std::int64_t>(&v, 1));
  }

  /// A float64 record of `total` values of which this rank has runs: run i is `length[i]`
  /// values from `start[i]` on, taken in turn from `values`, the starts increasing. On several
  /// ranks each rank writes its own runs into the file (write_together) and no rank holds the
  /// whole record; on one rank it is put() of the whole.
  void put_runs(const std::string& name, std::uint64_t total, std::vector<long long> start,
                std::vector<int> length, std::vector<double> values);
  /// Some record is a distributed one (put_runs on several ranks): the file is written with
  /// write_together, not write().
  bool distributed() const;
  /// Writes the file at `path` together with the other ranks (par::write_file_together): root
  /// the header and the records it holds whole, each rank its runs of the distributed ones,
  /// then root the checksum, which it reads the file back for, and flushes the file to the
  /// disk. The same bytes as write() of the whole records. Collective; throws OutputError on
  /// every rank when the file cannot be written (on root alone for the checksum).
  void write_together(const std::string& path) const;

  bool has(const std::string& name) const { return records_.count(name) > 0; }
  /// The record's values; an InputError naming the file and the record when it is missing, of
  /// another type, or (expected >= 0) not of `expected` values.
  const std::vector<double>& f64(const std::string& name, long long expected = -1) const;
  const std::vector<std::int64_t>& i64(const std::string& name, long long expected = -1) const;
  const std::vector<std::uint8_t>& u8(const std::string& name, long long expected = -1) const;
  const std::string& text(const std::string& name) const;
  double scalar(const std::string& name) const { return f64(name, 1)[0]; }
  std::int64_t integer(const std::string& name) const { return i64(name, 1)[0]; }

  /// The whole file: header and payload.
  std::string serialize() const;
  /// The same bytes, handed to `sink` piece by piece (the header, then each record's own
  /// header and its values straight from the record): a file written this way needs no copy of
  /// the payload in memory.
  void write(const std::function<void(std::string_view)>& sink) const;
  /// Reads a file's bytes; `label` names it in messages. Throws InputError.
  static CheckpointFile parse(std::string_view bytes, const std::string& label);
  /// Reads the file at `path` on every rank without any rank holding its large records (a
  /// distributed restart, issue 21): root checks the checksum, reading the file in pieces,
  /// every rank checks the records' heads and reads the records of fewer than `in_file_from`
  /// float64 values; the larger ones stay in the file, read where f64_runs asks (or whole by
  /// f64, on first use). Collective; throws the same InputError, naming the file, on every rank.
  static CheckpointFile read_together(const std::string& path, std::uint64_t in_file_from);
  /// A float64 record's values at its runs (start[i], length[i]), in turn: from the file for
  /// one that read_together left there, else from those held. InputError as f64().
  std::vector<double> f64_runs(const std::string& name, long long expected,
                               std::span<const long long> start, std::span<const int> length) const;
  const std::string& label() const { return label_; }

 private:
  struct Source;
  static CheckpointFile parse_from(const Source& src, const std::string& label,
                                   std::uint64_t in_file_from);
  const Record& get(const std::string& name, Type type, long long expected) const;
  /// The payload's pieces, in order.
  void payload(const std::function<void(std::string_view)>& piece) const;
  std::map<std::string, Record> records_;
  std::string label_;
  std::string path_;  ///< the file read_together read (its in-file records' source)
};

}  // namespace hencky
