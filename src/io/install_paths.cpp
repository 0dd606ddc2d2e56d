#include "io/install_paths.hpp"

#include <filesystem>

#include "core/error.hpp"

namespace weft {

namespace fs = std::filesystem;

std::string executable_dir() {
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string() : program.parent_path().string();
}

std::string find_data_dir(const std::vector<std::string>& folders, const std::string& marker,
                          const std::string& what) {
  std::string tried;
  for (const std::string& folder : folders) {
    if (folder.empty()) continue;
    const fs::path dir = fs::path(folder).lexically_normal();
    std::error_code error;
    if (fs::is_regular_file(dir / marker, error)) return dir.string();
    tried += (tried.empty() ? "" : ", ") + dir.string();
  }
  throw IoError("cannot find " + what + " (" + marker +
                "); looked in: " + (tried.empty() ? "nowhere" : tried));
}

}  // namespace weft
