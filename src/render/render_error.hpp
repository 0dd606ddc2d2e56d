#pragma once
// Errors of the OpenGL side: a shader that does not compile, a missing shader file.
#include <stdexcept>

namespace weft {

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace weft
