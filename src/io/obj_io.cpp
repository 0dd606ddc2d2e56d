#include "io/obj_io.hpp"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace weft {

namespace {

std::string read_text(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw IoError(path + ": is a directory, not a file");
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    // The whole path tried: a relative one was resolved against a folder the reader may not guess.
    const int cause = errno;
    const std::string tried = std::filesystem::absolute(path, error).lexically_normal().string();
    throw IoError((tried.empty() ? path : tried) + ": cannot open file: " + std::strerror(cause));
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw IoError(path + ": cannot read file");
  return text.str();
}

// Reads up to `count` numbers separated by blanks from [begin, end); returns how many it read.
int parse_numbers(const char* begin, const char* end, double* values, int count) {
  int read = 0;
  while (read < count) {
    while (begin < end && (*begin == ' ' || *begin == '\t')) ++begin;
    if (begin < end && *begin == '+') ++begin;
    const auto [next, error] = std::from_chars(begin, end, values[read]);
    if (error != std::errc() || (next < end && *next != ' ' && *next != '\t')) break;
    begin = next;
    ++read;
  }
  return read;
}

// Vertex and texture coordinates in file order, at double precision.
struct ObjCoordinates {
  std::vector<double> positions;  // x, y, z per `v` statement
  std::vector<double> uvs;        // u, v per `vt` statement
};

// Calls visit(line_number, first, end) for each line of `text`, numbered from 1, with its
// leading blanks skipped. Lines end at "\n", "\r\n" or "\r", as tinyobjloader's do, so line
// numbers and statement counts agree with its parse.
template <typename Visit>
void for_each_line(const std::string& text, Visit visit) {
  int line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t stop = text.find_first_of("\r\n", start);
    if (stop == std::string::npos) stop = text.size();
    const char* token = text.data() + start;
    const char* const line_end = text.data() + stop;
    start = stop + ((stop + 1 < text.size() && text[stop] == '\r' && text[stop + 1] == '\n') ? 2 : 1);
    ++line_number;
    while (token < line_end && (*token == ' ' || *token == '\t')) ++token;
    visit(line_number, token, line_end);
  }
}

// The packaged tinyobjloader stores coordinates as float, so `v` and `vt` statements are read
// again here at full precision (and checked, with line numbers); a statement is recognised
// exactly as tinyobjloader does, so the counts agree.
ObjCoordinates read_coordinates(const std::string& text, const std::string& path) {
  ObjCoordinates coordinates;
  for_each_line(text, [&](int line_number, const char* token, const char* line_end) {
    const auto is_blank = [&](const char* c) { return c < line_end && (*c == ' ' || *c == '\t'); };
    const auto fail = [&](const std::string& what) {
      throw IoError(path + ": line " + std::to_string(line_number) + ": " + what);
    };
    double values[3] = {0.0, 0.0, 0.0};
    if (token < line_end && token[0] == 'v' && is_blank(token + 1)) {
      if (parse_numbers(token + 2, line_end, values, 3) < 3) {
        fail("expected three numbers after `v`");
      }
      coordinates.positions.insert(coordinates.positions.end(), values, values + 3);
    } else if (token + 1 < line_end && token[0] == 'v' && token[1] == 't' && is_blank(token + 2)) {
      if (parse_numbers(token + 3, line_end, values, 2) < 1) {
        fail("expected one or two numbers after `vt`");
      }
      coordinates.uvs.insert(coordinates.uvs.end(), values, values + 2);
    } else {
      return;
    }
    if (!(std::isfinite(values[0]) && std::isfinite(values[1]) && std::isfinite(values[2]))) {
      fail("non-finite coordinate");
    }
  });
  return coordinates;
}

// The line of each triangle tinyobjloader makes: an `f` statement of n corners gives n - 2 in
// file order. Empty when the counts disagree (a polygon tinyobjloader triangulated otherwise),
// so messages then name the triangle alone.
std::vector<int> triangle_lines(const std::string& text, Eigen::Index num_triangles) {
  std::vector<int> lines;
  for_each_line(text, [&](int line_number, const char* token, const char* line_end) {
    if (line_end - token < 2 || token[0] != 'f' || (token[1] != ' ' && token[1] != '\t')) return;
    int corners = 0;
    for (const char* c = token + 1; c < line_end;) {
      while (c < line_end && (*c == ' ' || *c == '\t')) ++c;
      if (c == line_end) break;
      ++corners;
      while (c < line_end && *c != ' ' && *c != '\t') ++c;
    }
    for (int k = 0; k + 2 < corners; ++k) lines.push_back(line_number);
  });
  if (static_cast<Eigen::Index>(lines.size()) != num_triangles) lines.clear();
  return lines;
}

// Rewrites a tinyobjloader parse error, e.g. "Failed parse `f' line(...line 3.)", as "line 3: ...".
std::string describe_parse_error(const std::string& error) {
  std::string where;
  for (std::size_t at = error.find("line "); at != std::string::npos; at = error.find("line ", at + 1)) {
    const std::size_t digits = error.find_first_not_of("0123456789", at + 5);
    if (digits > at + 5) where = "line " + error.substr(at + 5, digits - (at + 5)) + ": ";
  }
  const std::size_t quote = error.find('`');
  const char statement = quote != std::string::npos && quote + 1 < error.size() ? error[quote + 1] : '?';
  if (statement == 'f' || statement == 'l' || statement == 'p') {
    return where + "expected non-zero vertex indices in `" + statement + "` statement";
  }
  return where + error.substr(0, error.find('\n'));
}

void append_number(std::string& out, double value) {
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

void append_index(std::string& out, int value) {
  char buffer[16];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

}  // namespace

TriangleMesh read_obj(const std::string& path) { return parse_obj(read_text(path), path); }

TriangleMesh parse_obj(const std::string& text, const std::string& path) {
  const ObjCoordinates coordinates = read_coordinates(text, path);

  // tinyobjloader parses the faces and triangulates polygons; without a material reader it
  // ignores `mtllib`.
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning, error;
  std::istringstream stream(text);
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &stream, nullptr, true, false)) {
    throw IoError(path + ": " + describe_parse_error(error));
  }
  if (warning.find("Degenerated face") != std::string::npos) {
    throw IoError(path + ": a face has fewer than three vertices");
  }
  if (warning.find("invalid vertex index") != std::string::npos) {
    throw IoError(path + ": a polygon has a vertex index out of range");
  }
  const int num_vertices = static_cast<int>(coordinates.positions.size() / 3);
  const int num_uvs = static_cast<int>(coordinates.uvs.size() / 2);
  if (attrib.vertices.size() != coordinates.positions.size() ||
      attrib.texcoords.size() != coordinates.uvs.size()) {
    throw IoError(path + ": cannot read coordinates consistently (tinyobjloader and weft disagree)");
  }

  // All shapes index the same vertex list, so their triangles merge into one mesh as they are.
  std::vector<tinyobj::index_t> corners;
  for (const tinyobj::shape_t& shape : shapes) {
    corners.insert(corners.end(), shape.mesh.indices.begin(), shape.mesh.indices.end());
  }
  if (corners.empty()) throw IoError(path + ": no triangles");

  TriangleMesh mesh;
  mesh.positions = Eigen::Map<const Positions>(coordinates.positions.data(), 3, num_vertices);
  mesh.triangles.resize(3, static_cast<Eigen::Index>(corners.size() / 3));
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const int v = corners[c].vertex_index;
    if (v < 0 || v >= num_vertices) {
      throw IoError(path + ": vertex index " + std::to_string(v + 1) + " out of range (the file has " +
                    std::to_string(num_vertices) + " vertices)");
    }
    const int uv = corners[c].texcoord_index;
    if (uv < -1 || uv >= num_uvs) {
      throw IoError(path + ": texture coordinate index " + std::to_string(uv + 1) +
                    " out of range (the file has " + std::to_string(num_uvs) + ")");
    }
    mesh.triangles(c % 3, c / 3) = v;
  }
  // A repeated vertex or two corners at one point: the triangle has no shape, and its normal,
  // rest strain and contact distances divide by zero.
  const std::vector<int> lines = triangle_lines(text, mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3i tri = mesh.triangles.col(t);
    const std::string where = path + ": " + (lines.empty() ? "" : "line " + std::to_string(lines[t]) + ": ") +
                              "triangle " + std::to_string(t + 1);
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      throw IoError(where + " repeats vertex (" + std::to_string(tri[0] + 1) + ", " +
                    std::to_string(tri[1] + 1) + ", " + std::to_string(tri[2] + 1) + ")");
    }
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      if (mesh.positions.col(a) == mesh.positions.col(b)) {
        std::ostringstream point;
        point << mesh.positions(0, a) << ", " << mesh.positions(1, a) << ", " << mesh.positions(2, a);
        throw IoError(where + " has a zero-length edge: vertices " + std::to_string(a + 1) + " and " +
                      std::to_string(b + 1) + " are both at (" + point.str() +
                      "); expected the corners of a triangle at distinct points");
      }
    }
  }

  // Per-vertex texture coordinates, kept only if every corner has one and each vertex has a
  // single value (a seam, where a vertex has two, drops them all).
  const Eigen::Map<const Eigen::Matrix2Xd> file_uvs(coordinates.uvs.data(), 2, num_uvs);
  Eigen::Matrix2Xd uvs = Eigen::Matrix2Xd::Zero(2, num_vertices);
  std::vector<bool> assigned(num_vertices, false);
  bool single_uv = true;
  for (std::size_t c = 0; c < corners.size() && single_uv; ++c) {
    const int v = corners[c].vertex_index;
    const int uv = corners[c].texcoord_index;
    if (uv < 0) {
      single_uv = false;
    } else if (!assigned[v]) {
      uvs.col(v) = file_uvs.col(uv);
      assigned[v] = true;
    } else {
      single_uv = uvs.col(v) == file_uvs.col(uv);
    }
  }
  if (single_uv) mesh.uvs = std::move(uvs);
  return mesh;
}

void write_obj(std::ostream& out, const std::vector<ObjObject>& objects) {
  // OBJ indices are 1-based and count across the whole file.
  int position_offset = 1, uv_offset = 1, normal_offset = 1;
  std::string text;
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const ObjObject& object = objects[o];
    if (object.positions == nullptr || object.triangles == nullptr) {
      throw std::invalid_argument("write_obj: object \"" + object.name + "\" has no positions or triangles");
    }
    const Positions& positions = *object.positions;
    const Triangles& triangles = *object.triangles;
    const bool write_uvs = object.uvs != nullptr && object.uvs->cols() > 0;
    if (write_uvs && object.uvs->cols() != positions.cols()) {
      throw std::invalid_argument("write_obj: object \"" + object.name + "\" has " +
                                  std::to_string(object.uvs->cols()) + " uvs for " +
                                  std::to_string(positions.cols()) + " vertices");
    }

    // A name is the rest of its line, so line breaks in it become underscores.
    std::string name = object.name.empty() ? "object_" + std::to_string(o) : object.name;
    for (char& c : name) {
      if (c == '\n' || c == '\r') c = '_';
    }
    text = "o " + name + "\n";

    // Shortest decimal forms that read back as the same doubles.
    const auto append_vector = [&](const char* keyword, const auto& vector) {
      text += keyword;
      for (Eigen::Index k = 0; k < vector.size(); ++k) {
        text += ' ';
        append_number(text, vector[k]);
      }
      text += '\n';
    };
    for (Eigen::Index i = 0; i < positions.cols(); ++i) append_vector("v", positions.col(i));
    if (write_uvs) {
      for (Eigen::Index i = 0; i < positions.cols(); ++i) append_vector("vt", object.uvs->col(i));
    }
    if (object.write_normals) {
      const Positions normals = vertex_normals(positions, triangles);
      for (Eigen::Index i = 0; i < normals.cols(); ++i) append_vector("vn", normals.col(i));
    }

    // Faces as v, v/vt, v//vn or v/vt/vn; the three indices of a corner are the same vertex.
    for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
      text += 'f';
      for (int k = 0; k < 3; ++k) {
        const int v = triangles(k, t);
        text += ' ';
        append_index(text, position_offset + v);
        if (write_uvs || object.write_normals) text += '/';
        if (write_uvs) append_index(text, uv_offset + v);
        if (object.write_normals) {
          text += '/';
          append_index(text, normal_offset + v);
        }
      }
      text += '\n';
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));

    const int n = static_cast<int>(positions.cols());
    position_offset += n;
    if (write_uvs) uv_offset += n;
    if (object.write_normals) normal_offset += n;
  }
}

void write_obj_file(const std::string& path, const TriangleMesh& mesh, const std::string& name) {
  const ObjObject object{name, &mesh.positions, &mesh.triangles, mesh.has_uvs() ? &mesh.uvs : nullptr, true};
  write_file_atomically(path, [&](std::ostream& out) { write_obj(out, {object}); });
}

}  // namespace weft
