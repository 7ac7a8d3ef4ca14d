// The checkpoint reader (output/checkpoint_file.hpp, output/checkpoint.hpp) on any bytes: the
// container, then the restore of its records into a model (restore_run: the fingerprints, every
// record's size, the contact and heat records).
//
// The input's size and CRC-32 fields are set to match its data before it is read, so that
// mutations reach the records behind the checksum (which a mutated file would almost never
// match); the checks of the header, the size and the checksum themselves are the unit tests'
// (tests/unit/test_checkpoint.cpp: every truncation and every changed byte).
// The model is tests/cli/inputs/restart (one plastic hexahedron under a rigid lid), read once;
// the seeds are its checkpoints (fuzz/corpus/checkpoint).
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "fuzz_support.hpp"
#include "input/load_case.hpp"
#include "output/checkpoint.hpp"

namespace {
hencky::Log model_log;  // the model keeps a reference
std::unique_ptr<hencky::LoadedCase> loaded;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  model_log.silent = true;
  loaded = std::make_unique<hencky::LoadedCase>(
      hencky::load_case(HENCKY_SOURCE_DIR "/tests/cli/inputs/restart/case.yaml", model_log));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  std::string bytes(fuzz::text_of(data, size));
  constexpr std::size_t header = 32;
  if (bytes.size() >= header) {
    const std::uint64_t payload = bytes.size() - header;
    const std::uint32_t crc = crc32(std::string_view(bytes).substr(header));
    std::memcpy(bytes.data() + 16, &payload, 8);
    std::memcpy(bytes.data() + 24, &crc, 4);
  }
  const std::string file = "fuzz.hckp";
  fuzz::expect_input_error_or_success(file, [&] {
    const CheckpointFile f = CheckpointFile::parse(bytes, file);
    restore_run(*loaded->model, f);
  });
  return 0;
}
