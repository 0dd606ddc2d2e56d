#pragma once
// Wavefront OBJ input (tinyobjloader) and output.
#include <iosfwd>
#include <string>
#include <vector>

#include "core/triangle_mesh.hpp"

namespace weft {

// Reads every shape of an OBJ file into one mesh, triangulating polygons. Keeps per-vertex
// texture coordinates when each vertex has a single one. Throws IoError naming the file and
// what was wrong (missing file, parse error, no triangles, index out of range, NaN coordinate).
TriangleMesh read_obj(const std::string& path);

// The same from an OBJ file's text; `file` names it in errors (read_obj reads the file and
// calls this).
TriangleMesh parse_obj(const std::string& text, const std::string& file);

// One named object of an OBJ file.
struct ObjObject {
  std::string name;
  const Positions* positions = nullptr;      // 3 x n
  const Triangles* triangles = nullptr;      // 3 x m
  const Eigen::Matrix2Xd* uvs = nullptr;     // 2 x n, or null / empty for none
  bool write_normals = true;                 // area-weighted vertex normals
};

// Writes the objects as `o` blocks (v, vt, vn, f v/vt/vn) with full double precision.
void write_obj(std::ostream& out, const std::vector<ObjObject>& objects);

// Writes one mesh to `path` atomically (temporary file, then rename). Throws IoError.
void write_obj_file(const std::string& path, const TriangleMesh& mesh, const std::string& name);

}  // namespace weft
