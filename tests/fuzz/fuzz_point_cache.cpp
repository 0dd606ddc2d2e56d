// The point-cache (PC2) reader. A cache it accepts holds as many samples as its header counts,
// each of the header's point count.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/point_cache.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  weft::fuzz::expect_documented_errors([&] {
    const weft::PointCache cache = weft::read_point_cache(in, "fuzz.pc2");
    for (const Eigen::Matrix3Xf& sample : cache.samples) {
      if (sample.cols() != cache.num_points)
        weft::fuzz::finding("a sample's point count differs from the header's");
    }
  });
  return 0;
}
