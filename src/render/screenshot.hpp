#pragma once
// Saving what was drawn: reads the back buffer of the current GL context into a PNG file.
#include <string>

namespace weft {

// Call after drawing and before swapping buffers. Throws IoError if the file cannot be written.
void save_back_buffer_png(const std::string& path, int framebuffer_width, int framebuffer_height);

}  // namespace weft
