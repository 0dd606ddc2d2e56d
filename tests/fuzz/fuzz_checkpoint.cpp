// The checkpoint reader. The first byte picks what the rest is: even, a whole file; odd, a
// payload that the harness wraps in a valid header (version 2, 3 or 4 from the byte) and
// checksum, so that mutations reach the fields behind the checksum.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "fuzz_support.hpp"
#include "io/checkpoint.hpp"

namespace {

template <typename T>
void append(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::string file;
  if (data[0] % 2 == 0) {
    file = rest;
  } else {
    file = "WEFTCKPT";
    append<uint32_t>(file, 2 + (data[0] / 2) % 3);
    append<uint32_t>(file, 0);
    append<uint64_t>(file, rest.size());
    file += rest;
    append<uint64_t>(file, weft::checkpoint_checksum(rest));
  }
  weft::fuzz::expect_documented_errors([&] { weft::parse_checkpoint(file, "fuzz.bin"); });
  return 0;
}
