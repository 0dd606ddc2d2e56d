// The OBJ reader. A mesh it accepts has every triangle index in range, three distinct corners
// and finite positions (read_obj's contract).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/obj_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  weft::fuzz::expect_documented_errors([&] {
    const weft::TriangleMesh mesh = weft::parse_obj(text, "fuzz.obj");
    if (!mesh.positions.allFinite())
      weft::fuzz::finding("accepted a mesh with a coordinate that is not finite");
    for (int t = 0; t < mesh.num_triangles(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.triangles(k, t);
        if (v < 0 || v >= mesh.num_vertices()) weft::fuzz::finding("accepted a triangle index out of range");
      }
      if (mesh.triangles(0, t) == mesh.triangles(1, t) || mesh.triangles(1, t) == mesh.triangles(2, t) ||
          mesh.triangles(2, t) == mesh.triangles(0, t)) {
        weft::fuzz::finding("accepted a triangle that repeats a vertex");
      }
    }
  });
  return 0;
}
