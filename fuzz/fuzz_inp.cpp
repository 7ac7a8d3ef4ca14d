// The Abaqus/CalculiX deck reader (input/inp_reader: keywords, sets, surfaces, the node orders
// and the regions it makes), on any bytes. An *INCLUDE the bytes name is read from the working
// folder, and its errors name that file: any file name is accepted in an input error.
#include "fuzz_support.hpp"
#include "input/inp_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  fuzz::expect_input_error_or_success("", [&] {
    parse_inp(fuzz::text_of(data, size), "fuzz.inp", MeshReadOptions{});
  });
  return 0;
}
