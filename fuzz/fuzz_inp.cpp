// The Abaqus/CalculiX deck reader (input/inp_reader: keywords, sets, surfaces, the node orders
// and the regions it makes), and the same bytes as a deck run as the case (input/inp_case.hpp:
// materials, steps, conditions), on any bytes. An *INCLUDE the bytes name is read from the working
// folder, and its errors name that file: any file name is accepted in an input error.
#include "fuzz_support.hpp"
#include "input/inp_case.hpp"
#include "input/inp_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  fuzz::expect_input_error_or_success(
      "", [&] { parse_inp(fuzz::text_of(data, size), "fuzz.inp", MeshReadOptions{}); });
  fuzz::expect_input_error_or_success("",
                                      [&] { parse_deck(fuzz::text_of(data, size), "fuzz.inp"); });
  return 0;
}
