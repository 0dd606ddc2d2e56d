// The sweep file: parsed, then expanded into its cases as `weft sweep` does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/sweep_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  weft::fuzz::expect_documented_errors([&] {
    const weft::SweepDesc sweep = weft::parse_sweep(text, "sweeps/fuzz.json");
    weft::expand_sweep(sweep);
  });
  return 0;
}
