// The order conversion of a .msh (mesh.order: 1 or 2), hencky's way end to end: its own reader
// first (input/msh_reader), then, for a file it accepted, Gmsh's setOrder in a child process
// (input/gmsh_child), as `hencky run` does. Two crashes came this way (issue 47: a
// $PhysicalNames line of dimension 4, accepted by the reader, crashed Gmsh and hencky with it);
// now a crash inside Gmsh is an input error naming the file, and any other outcome is a bug.
// The child is this program started again: LLVMFuzzerInitialize hands that start to
// gmsh_child::child_main before libFuzzer reads its flags. One process per input: slow (tens
// of inputs a second), so the target is the readers' gate to Gmsh, not Gmsh itself.
#include <unistd.h>

#include <cstring>
#include <fstream>

#include "fuzz_support.hpp"
#include "input/gmsh_child.hpp"
#include "input/gmsh_reader.hpp"

namespace {
std::string scratch;  // this process's file of the input
}

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  hencky::run_gmsh_in_child_processes();
  if (*argc > 1 && std::strcmp((*argv)[1], hencky::gmsh_child::marker) == 0)
    _exit(hencky::gmsh_child::child_main(*argc, *argv));  // no leak check of Gmsh's own
  const char* tmp = std::getenv("TMPDIR");
  scratch = std::string(tmp && *tmp ? tmp : "/tmp") + "/hencky-fuzz-" + std::to_string(getpid()) +
            ".msh";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  {
    std::ofstream out(scratch, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  for (int order : {1, 2}) {
    MeshReadOptions options;
    options.order = order;
    fuzz::expect_input_error_or_success(scratch, [&] { read_gmsh(scratch, options); });
  }
  std::remove(scratch.c_str());
  return 0;
}
