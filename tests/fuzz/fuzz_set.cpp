// "--set path=value" overrides, one a line, applied to a small valid scene, which is then parsed.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/scene_file.hpp"

namespace {

// scenes/default.json, smaller: one pinned grid cloth and a ground plane.
const char* base_scene = R"({
  "name": "fuzz",
  "solver": {"integrator": "implicit_euler", "time_step": 0.001},
  "frames": 2,
  "cloths": [{"name": "cloth", "grid": {"size": [1, 1], "resolution": [2, 2]},
              "springs": {"structural": {"stiffness": 500}}, "pins": {"corners": ["top_left"]}}],
  "colliders": [{"type": "plane", "name": "ground", "point": [0, -1, 0], "normal": [0, 1, 0]}]
})";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
  weft::fuzz::expect_documented_errors([&] {
    nlohmann::json document = nlohmann::json::parse(base_scene);
    for (std::string line; std::getline(lines, line);) weft::apply_override(document, line);
    weft::parse_scene(document, "fuzz.json");
  });
  return 0;
}
