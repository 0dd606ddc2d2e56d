#include "io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.hpp"

namespace weft {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw IoError(path + ": cannot create file: " + std::strerror(errno));
    }
    try {
      write(out);
    } catch (...) {
      out.close();
      std::remove(temporary.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      const int error = errno;
      out.close();
      std::remove(temporary.c_str());
      throw IoError(path + ": write failed: " + (error != 0 ? std::strerror(error) : "stream error"));
    }
    out.close();
    if (out.fail()) {
      std::remove(temporary.c_str());
      throw IoError(path + ": write failed on close (disk full?)");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary.c_str());
    throw IoError(path + ": cannot rename temporary file into place: " + std::strerror(error));
  }
}

}  // namespace weft
