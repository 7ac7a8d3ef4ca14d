// The case reader (input/case_reader: read_case_text) on any text: YAML syntax, every
// section's keys and values, expressions, and the files a case names.
//
// The reader checks that the files the case names exist (the mesh, an STL body) and reads a
// temperature file: a folder made once per process holds the ones the seed corpus names
// (part.msh, part.geo, punch.stl, temps.csv), so that inputs get past those checks to the
// sections after them. The mesh itself is not read by read_case.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_support.hpp"
#include "input/case_reader.hpp"

namespace {

namespace fs = std::filesystem;

fs::path folder;

void remove_folder() {
  std::error_code ec;
  fs::remove_all(folder, ec);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::string name = (fs::temp_directory_path() / "hencky-fuzz-case-XXXXXX").string();
  if (!mkdtemp(name.data())) {
    std::perror("fuzz_case: mkdtemp");
    std::abort();
  }
  folder = name;
  std::atexit(remove_folder);
  for (const char* f : {"part.msh", "part.geo", "punch.stl"}) std::ofstream(folder / f) << "\n";
  std::ofstream(folder / "temps.csv") << "node,0,1\n1,20,100\n2,20,120\n";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  const fs::path file = folder / "case.yaml";
  fuzz::expect_input_error_or_success(
      "", [&] { read_case_text(std::string(fuzz::text_of(data, size)), file); });
  return 0;
}
