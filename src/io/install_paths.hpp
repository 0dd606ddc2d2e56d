#pragma once
// Where an installed weft finds its data (the viewer's shaders): beside the program, as
// `cmake --install` lays it out (PREFIX/bin/weft, PREFIX/share/weft/...), else in the source tree
// it was built from.
#include <string>
#include <vector>

namespace weft {

// The folder that holds the running program (/proc/self/exe); empty where it cannot be read.
std::string executable_dir();

// The first of `folders` that holds the file `marker`. Throws IoError naming `what` and every
// folder tried, in order.
std::string find_data_dir(const std::vector<std::string>& folders, const std::string& marker,
                          const std::string& what);

}  // namespace weft
