#pragma once
// Shared by the libFuzzer harnesses: what counts as a finding. The readers' documented errors
// (IoError, SceneError) are the expected answer to bad input; anything else that escapes, a
// sanitizer report, a crash or a hang is a finding.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "core/error.hpp"

namespace weft::fuzz {

// Stops the run with `what`: libFuzzer saves the input as a crash.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FINDING: %s\n", what.c_str());
  std::abort();
}

// Runs `read`; the documented error types return quietly, any other exception is a finding.
template <typename Read>
void expect_documented_errors(Read&& read) {
  try {
    read();
  } catch (const IoError&) {
  } catch (const SceneError&) {
  } catch (const std::exception& error) {
    finding(std::string("undocumented exception: ") + error.what());
  }
}

}  // namespace weft::fuzz
