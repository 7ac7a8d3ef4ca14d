// The nodal temperature file of temperature: {field: {file: ...}} (input/temperature_csv) on
// any bytes.
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "input/temperature_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  const std::string file = "fuzz.csv";
  fuzz::expect_input_error_or_success(file, [&] {
    std::istringstream in{std::string(fuzz::text_of(data, size))};
    TemperatureFile tf;
    case_input::read_temperature_rows(in, file, "temperature.field.file", tf);
  });
  return 0;
}
