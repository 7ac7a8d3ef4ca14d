// Times one reading of a Gmsh .msh file into hencky's mesh, by hencky's own reader or through
// the Gmsh library (the reader hencky used before), and reports the wall time and the peak
// memory of this process as one JSON line. Driven by bench/run_mesh_bench.py, one process per
// reading so that the peak memory is that reading's.
//   hencky_mesh_read_bench FILE.msh hencky|gmsh
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "input/gmsh_reader.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s FILE.msh hencky|gmsh\n", argv[0]);
    return 1;
  }
  hencky::MeshReadOptions options;
  options.through_gmsh_library = std::string(argv[2]) == "gmsh";
  const auto t0 = std::chrono::steady_clock::now();
  const hencky::Mesh mesh = hencky::read_gmsh(argv[1], options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  std::printf("{\"seconds\": %.6f, \"peak_bytes\": %ld, \"nodes\": %d, \"cells\": %d}\n", seconds,
              static_cast<long>(u.ru_maxrss) * 1024, mesh.n_nodes(), mesh.cells.size());
  return 0;
}
