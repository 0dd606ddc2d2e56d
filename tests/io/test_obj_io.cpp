// OBJ files: round trips at full precision, the written layout, polygons and shapes merged on
// reading, and errors that name the file.
#include "io/obj_io.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/mesh_generators.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

using weft::testing::TempDir;

std::string write_text(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

// Expects read_obj(path) to throw an IoError whose message names the file and contains `words`.
void expect_read_error(const std::string& path, const std::string& words) {
  try {
    read_obj(path);
    FAIL() << "expected an IoError mentioning " << words;
  } catch (const IoError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(words), std::string::npos) << message;
  }
}

TEST(ObjIo, GridRoundTripKeepsPositionsTrianglesAndUvs) {
  TempDir dir("weft_obj");
  TriangleMesh grid = make_grid(9, 7, 1.3, 0.7, GridTriangulation::cross);
  // Coordinates that no float can hold.
  transform_positions(grid.positions, rotation_from_euler_degrees(Vec3(12.3, 45.6, 78.9)), 1.0 / 3.0,
                      Vec3(1e-7, 123456.789, -2.0 / 3.0));
  const std::string path = dir.file("grid.obj");
  write_obj_file(path, grid, "cloth");

  const TriangleMesh read = read_obj(path);
  ASSERT_EQ(read.num_vertices(), grid.num_vertices());
  ASSERT_EQ(read.num_triangles(), grid.num_triangles());
  EXPECT_EQ(read.triangles, grid.triangles);
  EXPECT_LE((read.positions - grid.positions).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_TRUE(read.has_uvs());
  EXPECT_LE((read.uvs - grid.uvs).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ObjIo, SphereRoundTripWithoutUvs) {
  TempDir dir("weft_obj");
  const TriangleMesh sphere = make_uv_sphere(0.3, 11, 6);
  const std::string path = dir.file("sphere.obj");
  write_obj_file(path, sphere, "ball");
  const TriangleMesh read = read_obj(path);
  EXPECT_EQ(read.triangles, sphere.triangles);
  EXPECT_LE((read.positions - sphere.positions).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(read.has_uvs());
}

TEST(ObjIo, WritesEverySlashForm) {
  Positions positions(3, 3);
  positions << 0, 1, 0,  //
      0, 0, 1,           //
      0, 0, 0;
  Triangles triangles(3, 1);
  triangles << 0, 1, 2;
  Eigen::Matrix2Xd uvs(2, 3);
  uvs << 0, 1, 0,  //
      0, 0, 1;
  const auto written = [&](const Eigen::Matrix2Xd* object_uvs, bool normals) {
    std::ostringstream out;
    write_obj(out, {{"tri", &positions, &triangles, object_uvs, normals}});
    return lines_of(out.str());
  };
  EXPECT_EQ(written(&uvs, true).back(), "f 1/1/1 2/2/2 3/3/3");
  EXPECT_EQ(written(&uvs, false).back(), "f 1/1 2/2 3/3");
  EXPECT_EQ(written(nullptr, true).back(), "f 1//1 2//2 3//3");
  EXPECT_EQ(written(nullptr, false).back(), "f 1 2 3");
  EXPECT_EQ(written(&uvs, true),
            (std::vector<std::string>{"o tri", "v 0 0 0", "v 1 0 0", "v 0 1 0", "vt 0 0", "vt 1 0", "vt 0 1",
                                      "vn 0 0 1", "vn 0 0 1", "vn 0 0 1", "f 1/1/1 2/2/2 3/3/3"}));
}

TEST(ObjIo, OffsetsIndicesAcrossObjectsAndMergesThemOnReading) {
  TempDir dir("weft_obj");
  const TriangleMesh grid = make_grid(3, 3, 1.0, 1.0, GridTriangulation::regular);
  const TriangleMesh box = make_box(Vec3(1, 1, 1));
  // The box has no uvs, so the grid's vt indices continue past it in the third object.
  std::ostringstream out;
  write_obj(out, {{"first", &grid.positions, &grid.triangles, &grid.uvs, true},
                  {"box", &box.positions, &box.triangles, nullptr, true},
                  {"second", &grid.positions, &grid.triangles, &grid.uvs, false}});
  const std::vector<std::string> lines = lines_of(out.str());
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "o box"), 1);
  EXPECT_NE(std::find(lines.begin(), lines.end(), "f 10//10 14//14 16//16"), lines.end());
  EXPECT_NE(std::find(lines.begin(), lines.end(), "f 18/10 19/11 22/14"), lines.end());

  const std::string path = write_text(dir, "three.obj", out.str());
  const TriangleMesh read = read_obj(path);
  ASSERT_EQ(read.num_vertices(), 9 + 8 + 9);
  ASSERT_EQ(read.num_triangles(), 8 + 12 + 8);
  EXPECT_EQ(Triangles(read.triangles.leftCols(8)), grid.triangles);
  EXPECT_EQ(Triangles(read.triangles.middleCols(8, 12)), Triangles(box.triangles.array() + 9));
  EXPECT_EQ(Triangles(read.triangles.rightCols(8)), Triangles(grid.triangles.array() + 17));
  EXPECT_EQ(Positions(read.positions.middleCols(9, 8)), box.positions);
  EXPECT_FALSE(read.has_uvs());  // the box's corners have none
}

TEST(ObjIo, TriangulatesPolygons) {
  TempDir dir("weft_obj");
  const std::string path = write_text(dir, "polygons.obj",
                                      "# a unit square and a pentagon\r\n"
                                      "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                                      "v 2 0 0\r\nv 3 0 0\r\nv 3.5 1 0\r\nv 2.5 2 0\r\nv 1.5 1 0\r\n"
                                      "f 1 2 3 4\r\n"
                                      "f 5 6 7 8 9\r\n");
  const TriangleMesh mesh = read_obj(path);
  ASSERT_EQ(mesh.num_vertices(), 9);
  ASSERT_EQ(mesh.num_triangles(), 2 + 3);
  // Every triangle keeps the polygons' counter-clockwise winding.
  double area = 0.0;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 x0 = mesh.positions.col(mesh.triangles(0, t));
    const Vec3 normal =
        (mesh.positions.col(mesh.triangles(1, t)) - x0).cross(mesh.positions.col(mesh.triangles(2, t)) - x0);
    EXPECT_GT(normal.z(), 0.0);
    area += 0.5 * normal.norm();
  }
  EXPECT_NEAR(area, 1.0 + surface_area(mesh.positions, mesh.triangles.rightCols(3)), 1e-12);
  EXPECT_NEAR(surface_area(mesh.positions, mesh.triangles.leftCols(2)), 1.0, 1e-12);
}

TEST(ObjIo, KeepsSharedUvsAndDropsSeams) {
  TempDir dir("weft_obj");
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n";
  const TriangleMesh shared =
      read_obj(write_text(dir, "shared.obj", quad + "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"));
  ASSERT_TRUE(shared.has_uvs());
  EXPECT_EQ(shared.uvs.col(2), Vec2(1, 1));
  EXPECT_EQ(shared.uvs.col(3), Vec2(0, 1));
  // Vertex 3 has two texture coordinates: a seam, so no per-vertex uvs.
  const TriangleMesh seam = read_obj(write_text(dir, "seam.obj", quad + "f 1/1 2/2 3/3\nf 1/1 3/5 4/4\n"));
  EXPECT_EQ(seam.num_triangles(), 2);
  EXPECT_FALSE(seam.has_uvs());
  const TriangleMesh partial = read_obj(write_text(dir, "partial.obj", quad + "f 1/1 2/2 3/3\nf 1 3 4\n"));
  EXPECT_FALSE(partial.has_uvs());
}

TEST(ObjIo, MissingFile) {
  TempDir dir("weft_obj");
  expect_read_error(dir.file("missing.obj"), "cannot open file");
}

TEST(ObjIo, GarbageFile) {
  TempDir dir("weft_obj");
  const char binary[] =
      "\x7f"
      "ELF\x02\x01\x01\0\0\0 binary junk\n";
  expect_read_error(write_text(dir, "garbage.obj", std::string(binary, sizeof binary - 1)), "no triangles");
  expect_read_error(write_text(dir, "bad_vertex.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n"),
                    "line 2: expected three numbers");
  expect_read_error(write_text(dir, "zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 0 1 2\n"),
                    "line 5: expected non-zero vertex indices");
  expect_read_error(write_text(dir, "two_corners.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
                    "fewer than three vertices");
  expect_read_error(write_text(dir, "nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"),
                    "line 3: non-finite coordinate");
  expect_read_error(write_text(dir, "repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n"),
                    "line 4: triangle 1 repeats vertex");
}

TEST(ObjIo, ZeroLengthEdgeNamesLineTriangleAndVertices) {
  TempDir dir("weft_obj");
  expect_read_error(
      write_text(dir, "zero_edge.obj", "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n# x\nf 2 3 4\n"),
      "zero_edge.obj: line 7: triangle 2 has a zero-length edge: vertices 2 and 3 are both at (1, 0, 0)");
  // A quad makes two triangles of one line.
  expect_read_error(write_text(dir, "zero_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 1 0\nf 1 2 3 4\n"),
                    "line 5: triangle 2 has a zero-length edge");
}

TEST(ObjIo, IndexOutOfRange) {
  TempDir dir("weft_obj");
  expect_read_error(write_text(dir, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
                    "vertex index 7 out of range");
  expect_read_error(write_text(dir, "range_quad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 9\n"),
                    "out of range");
  expect_read_error(write_text(dir, "range_vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/4\n"),
                    "texture coordinate index 4 out of range");
}

TEST(ObjIo, FileWithoutFaces) {
  TempDir dir("weft_obj");
  expect_read_error(write_text(dir, "points.obj", "o cloud\nv 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n"),
                    "no triangles");
  expect_read_error(write_text(dir, "empty.obj", ""), "no triangles");
}

TEST(ObjIo, WriteFileFailsIntoMissingFolder) {
  TempDir dir("weft_obj");
  const TriangleMesh box = make_box(Vec3(1, 1, 1));
  const std::string path = dir.file("no_such_folder/box.obj");
  try {
    write_obj_file(path, box, "box");
    FAIL() << "expected an IoError";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace weft
