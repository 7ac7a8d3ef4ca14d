// The STL reader (contact/stl_surface: ASCII and binary) on any bytes, and the queries the
// contact makes of a surface it accepted.
#include "contact/stl_surface.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hencky;
  const std::string file = "fuzz.stl";
  fuzz::expect_input_error_or_success(file, [&] {
    const StlSurface s(fuzz::text_of(data, size), file, 1.0);
    // The accepted surface is a closed solid: its bounding-volume hierarchy must answer from
    // inside, outside and on the box, along a segment through it too.
    const Vec3 lo = s.box_min(), hi = s.box_max(), mid = (lo + hi) / 2;
    for (const Vec3& p : {mid, lo, hi, Vec3(2 * hi - lo)}) {
      s.signed_distance(p);
      s.nearest(p);
    }
    s.intersection(2 * lo - hi, 2 * hi - lo);
  });
  return 0;
}
