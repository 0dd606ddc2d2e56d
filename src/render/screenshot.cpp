#include "render/screenshot.hpp"

#include <glad/gl.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/error.hpp"

namespace weft {

void save_back_buffer_png(const std::string& path, int framebuffer_width, int framebuffer_height) {
  const int row_bytes = 3 * framebuffer_width;
  std::vector<unsigned char> pixels(static_cast<size_t>(row_bytes) * framebuffer_height);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, framebuffer_width, framebuffer_height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // GL's rows go bottom to top, PNG's top to bottom.
  std::vector<unsigned char> flipped(pixels.size());
  for (int row = 0; row < framebuffer_height; ++row) {
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(row_bytes) * row, row_bytes,
                flipped.begin() + static_cast<std::ptrdiff_t>(row_bytes) * (framebuffer_height - 1 - row));
  }
  if (stbi_write_png(path.c_str(), framebuffer_width, framebuffer_height, 3, flipped.data(), row_bytes) ==
      0) {
    throw IoError(path + ": cannot write PNG screenshot");
  }
}

}  // namespace weft
