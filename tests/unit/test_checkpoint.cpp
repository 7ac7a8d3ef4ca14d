// The checkpoint container (output/checkpoint_file.hpp): a round trip keeps every value to the
// bit, the CRC-32 is the standard one, and every truncation, every changed byte and a newer
// format version are InputErrors, never a crash or a wrong value. The whole state's round trip
// and the restarts are checked end to end (tests/cli/cases/60_restart.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <tuple>

#include "core/error.hpp"
#include "output/checkpoint_file.hpp"
#include "parallel/mpi.hpp"
#include "verify_support.hpp"

namespace hencky {
namespace {

CheckpointFile sample() {
  CheckpointFile f;
  const double d[] = {0.1, -0.0, std::numeric_limits<double>::denorm_min(), 1e308, NAN};
  f.put("doubles", std::span<const double>(d));
  const std::int64_t i[] = {-1, 0, std::numeric_limits<std::int64_t>::max()};
  f.put("integers", std::span<const std::int64_t>(i));
  const std::uint8_t b[] = {0, 1, 255};
  f.put("bytes", std::span<const std::uint8_t>(b));
  f.put("text", std::string("a\nb, é"));
  f.put("empty", std::span<const double>());
  f.put("time", 0.3);
  return f;
}

TEST(CheckpointFile, Crc32IsTheStandardOne) {
  // The check value of CRC-32/ISO-HDLC (zlib's crc32).
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(crc32(""), 0u);
  EXPECT_EQ(crc32("6789", crc32("12345")), 0xCBF43926u);  // continued piece by piece
}

TEST(CheckpointFile, RoundTripKeepsEveryBit) {
  const std::string bytes = sample().serialize();
  const CheckpointFile g = CheckpointFile::parse(bytes, "x.hckp");
  const auto& d = g.f64("doubles", 5);
  EXPECT_EQ(d[0], 0.1);
  EXPECT_TRUE(std::signbit(d[1]));
  EXPECT_EQ(d[2], std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(d[3], 1e308);
  EXPECT_TRUE(std::isnan(d[4]));
  EXPECT_EQ(g.i64("integers")[2], std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(g.u8("bytes")[2], 255);
  EXPECT_EQ(g.text("text"), "a\nb, é");
  EXPECT_TRUE(g.f64("empty").empty());
  EXPECT_EQ(g.scalar("time"), 0.3);
  EXPECT_EQ(g.serialize(), bytes);  // the same records give the same file
}

TEST(CheckpointFile, MissingOrMistypedRecordsNameTheRecord) {
  const CheckpointFile g = CheckpointFile::parse(sample().serialize(), "x.hckp");
  EXPECT_THROW(g.f64("nothing"), InputError);
  try {
    g.f64("doubles", 4);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.hckp: checkpoint record 'doubles' has 5 values, "
                                         "expected 4"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(g.i64("doubles"), InputError);
  EXPECT_THROW(g.text("bytes"), InputError);
}

TEST(CheckpointFile, EveryTruncationAndEveryChangedByteIsAnInputError) {
  const std::string bytes = sample().serialize();
  for (std::size_t n = 0; n < bytes.size(); ++n)
    EXPECT_THROW(CheckpointFile::parse(bytes.substr(0, n), "x"), InputError) << n << " bytes";
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    if (at >= 12 && at < 16) continue;  // reserved: not read
    if (at >= 28 && at < 32) continue;
    std::string b = bytes;
    b[at] = static_cast<char>(b[at] ^ 0x01);
    EXPECT_THROW(CheckpointFile::parse(b, "x"), InputError) << "byte " << at;
  }
}

TEST(CheckpointFile, ANewerFormatIsRefusedByName) {
  std::string b = sample().serialize();
  const std::uint32_t v = checkpoint_format_version + 1;
  std::memcpy(b.data() + 8, &v, 4);
  try {
    CheckpointFile::parse(b, "x.hckp");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("written by a newer hencky"), std::string::npos)
        << e.what();
  }
}

TEST(CheckpointFile, AConsistentFileWithAnAbsurdCountIsRefused) {
  // A record that announces more values than the file holds, behind a valid checksum (a file
  // made by hand, or a bug): refused before anything is allocated.
  std::string payload;
  const std::uint32_t name_size = 1;
  payload.append(reinterpret_cast<const char*>(&name_size), 4);
  payload += 'u';
  payload += static_cast<char>(1);
  const std::uint64_t count = std::uint64_t{1} << 60;
  payload.append(reinterpret_cast<const char*>(&count), 8);
  std::string b = "HNCKCKPT";
  const std::uint32_t version = 1, zero = 0, crc = crc32(payload);
  const std::uint64_t size = payload.size();
  b.append(reinterpret_cast<const char*>(&version), 4);
  b.append(reinterpret_cast<const char*>(&zero), 4);
  b.append(reinterpret_cast<const char*>(&size), 8);
  b.append(reinterpret_cast<const char*>(&crc), 4);
  b.append(reinterpret_cast<const char*>(&zero), 4);
  b += payload;
  EXPECT_THROW(CheckpointFile::parse(b, "x"), InputError);
}

// A checkpoint of a distributed mesh is written by every rank into the one file (issue 21):
// each rank its runs of the nodal and point records, root the header, the other records and
// the checksum. The file must be byte for byte the one a rank holding every record writes.
// Runs of 7 values dealt out to the ranks in turn, and a record no rank has runs of, stand for
// the owners' nodes and the parts' cells. Run on 1 rank and on 3 (ctest mpi_node_exchange).
TEST(SharedFile, TheRanksWriteTheWholeFilesBytes) {
  par::ensure_petsc();
  const int ranks = par::size(), me = par::rank();
  const auto runs = [&](std::size_t total, double scale) {
    std::vector<long long> start;
    std::vector<int> length;
    std::vector<double> values;
    for (std::size_t s = 0, k = 0; s < total; s += 7, ++k)
      if (static_cast<int>(k % ranks) == me) {
        start.push_back(static_cast<long long>(s));
        length.push_back(static_cast<int>(std::min<std::size_t>(7, total - s)));
        for (std::size_t i = s; i < s + length.back(); ++i) values.push_back(scale * i + 0.25);
      }
    return std::make_tuple(start, length, values);
  };
  const auto whole = [](std::size_t total, double scale) {
    std::vector<double> v(total);
    for (std::size_t i = 0; i < total; ++i) v[i] = scale * i + 0.25;
    return v;
  };
  CheckpointFile shared, one;
  for (CheckpointFile* f : {&shared, &one}) {
    f->put("title", std::string("a distributed model"));
    f->put("time", 0.5);
    const std::int64_t counts[3] = {4, 17, 2};
    f->put("counts", std::span<const std::int64_t>(counts));
    const std::uint8_t flags[2] = {1, 0};
    f->put("flags", std::span<const std::uint8_t>(flags));
  }
  auto [s1, l1, v1] = runs(1000, 0.5);
  shared.put_runs("points.stress", 1000, s1, l1, v1);
  auto [s2, l2, v2] = runs(45, -3.0);
  shared.put_runs("u", 45, s2, l2, v2);
  shared.put_runs("empty", 0, {}, {}, {});
  one.put("points.stress", std::span<const double>(whole(1000, 0.5)));
  one.put("u", std::span<const double>(whole(45, -3.0)));
  one.put("empty", std::span<const double>());
  EXPECT_EQ(shared.distributed(), ranks > 1);

  verify::TempDir dir("shared_file");
  std::string path = (dir / "step.hckp").string();
  par::broadcast(path);  // root's folder
  shared.write_together(path);
  std::string bytes;  // as written, on root
  if (par::root()) {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // Read back without any rank holding the large records: each reads its runs where they are.
  const CheckpointFile part = CheckpointFile::read_together(path, 100);
  const std::vector<long long> start = {993, 0, 500, 507};
  const std::vector<int> length = {7, 3, 7, 2};
  const std::vector<double> runs_read = part.f64_runs("points.stress", 1000, start, length);
  const std::vector<double> all = whole(1000, 0.5);
  std::vector<double> expected;
  for (std::size_t i = 0; i < start.size(); ++i)
    expected.insert(expected.end(), all.begin() + start[i], all.begin() + start[i] + length[i]);
  EXPECT_EQ(runs_read, expected);
  EXPECT_EQ(part.f64("u", 45), whole(45, -3.0));    // below 100 values: read whole
  EXPECT_EQ(part.f64("points.stress", 1000), all);  // read whole on first use
  EXPECT_EQ(part.text("title"), "a distributed model");
  EXPECT_THROW(part.f64_runs("points.stress", 999, start, length), InputError);  // its length
  // A damaged file: root finds the checksum wrong, and every rank stops with its message.
  if (par::root()) {
    std::fstream damage(path, std::ios::in | std::ios::out | std::ios::binary);
    damage.seekp(-3, std::ios::end);
    damage.put('\x7f');
  }
  par::any(false);  // the damage is done before any rank reads
  try {
    CheckpointFile::read_together(path, 100);
    ADD_FAILURE() << "a damaged file was read";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("checksum"), std::string::npos) << e.what();
  }
  if (!par::root()) return;
  EXPECT_EQ(bytes, one.serialize());
  const CheckpointFile back = CheckpointFile::parse(bytes, path);
  EXPECT_EQ(back.f64("points.stress", 1000), whole(1000, 0.5));
  EXPECT_EQ(back.f64("u", 45), whole(45, -3.0));
}

TEST(SharedFile, AFileThatCannotBeWrittenStopsEveryRank) {
  par::ensure_petsc();
  CheckpointFile f;
  f.put_runs("u", 3, {0}, {3}, {1, 2, 3});
  EXPECT_THROW(f.write_together("/nonexistent-folder/step.hckp"), OutputError);
}

}  // namespace
}  // namespace hencky
