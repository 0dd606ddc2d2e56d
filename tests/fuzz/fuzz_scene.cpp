// The scene loader: a scene file's text, then (after a NUL byte) one "--set path=value" a line.
// A scene that parses must read back from its resolved form (scene_to_json), as run.json and
// checkpoints are read on --resume.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t nul = input.find('\0');
  const std::string text = input.substr(0, nul);
  std::vector<std::string> overrides;
  if (nul != std::string::npos) {
    std::istringstream lines(input.substr(nul + 1));
    for (std::string line; std::getline(lines, line);) overrides.push_back(line);
  }
  weft::fuzz::expect_documented_errors([&] {
    const weft::SceneDesc scene = weft::parse_scene_text(text, "fuzz.json", overrides);
    try {
      weft::parse_scene(weft::scene_to_json(scene), "resolved.json");
    } catch (const weft::SceneError& error) {
      weft::fuzz::finding(std::string("a parsed scene does not read back from scene_to_json: ") +
                          error.what());
    }
  });
  return 0;
}
