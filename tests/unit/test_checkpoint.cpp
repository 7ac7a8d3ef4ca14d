// The checkpoint container (output/checkpoint_file.hpp): a round trip keeps every value to the
// bit, the CRC-32 is the standard one, and every truncation, every changed byte and a newer
// format version are InputErrors, never a crash or a wrong value. The whole state's round trip
// and the restarts are checked end to end (tests/cli/cases/60_restart.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "output/checkpoint_file.hpp"

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

}  // namespace
}  // namespace hencky
