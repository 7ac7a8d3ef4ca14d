// The .msh reader (input/msh_reader: formats 2.2, 4.0 and 4.1, ASCII and binary) and the
// conversion of what it read to the solver's mesh (input/msh_data: to_mesh), on any bytes.
#include "fuzz_support.hpp"
#include "input/msh_data.hpp"
#include "input/msh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  const std::string file = "fuzz.msh";
  fuzz::expect_input_error_or_success(file, [&] {
    const MshData msh = parse_msh(fuzz::text_of(data, size), file);
    // Order 0 keeps the file's order: the Gmsh library is never called (it is not safe with
    // malformed input, docs/development.md), as for a .msh the case names.
    to_mesh(msh, MeshReadOptions{}, file);
  });
  return 0;
}
