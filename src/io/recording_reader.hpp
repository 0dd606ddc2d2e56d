#pragma once
// Reading a headless run's recording back (io/recording.hpp writes it): DIR/run.json (the resolved
// scene: the colliders' shapes, the frame rate), DIR/recording.json (the cloths' names and files,
// mesh colliders' triangles), each cloth's rest OBJ and PC2 cache (or the OBJ frame files) and
// colliders.csv (each collider's placement per frame). For `weft check` and `weft view`.
#include <filesystem>
#include <string>
#include <vector>

#include "collision/collider.hpp"
#include "core/math.hpp"
#include "core/triangle_mesh.hpp"
#include "io/point_cache.hpp"
#include "sim/scene_desc.hpp"

namespace weft {

// A collider's placement at one frame: a point x of it at time 0 is at rotation * x + translation.
struct Placement {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
};

struct RecordedCloth {
  std::string name;
  Triangles triangles;
  int vertices = 0;
  PointCache cache;  // empty when the recording has OBJ frames only
};

struct RecordedCollider {
  Collider collider;
  TriangleMesh surface;  // at time 0
};

// Everything a recording holds, frame by frame.
struct Recording {
  std::filesystem::path dir;
  SceneDesc scene;  // run.json's resolved scene
  int frames = 0;   // frames every cloth has
  double fps = 0.0;
  std::vector<RecordedCloth> cloths;
  std::vector<RecordedCollider> colliders;
  std::vector<std::vector<Placement>> placements;  // per frame, per collider
  std::string frame_file_pattern;                  // OBJ frames: "frame_%0Nd.obj", else empty
};

// Reads the recording in `dir`; throws IoError naming the file, the field and what was expected.
Recording read_recording(const std::filesystem::path& dir);

// Every cloth's positions at `frame` (below recording.frames), from the point caches or the
// frame's OBJ file (whose first read also gives the cloths' triangles). Throws IoError.
std::vector<Positions> cloth_positions(Recording& recording, int frame);

// A run's stats.csv: its columns and one row of numbers per frame.
struct StatsTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  // The column's index, -1 if the table has none of that name.
  int column(const std::string& name) const;
};

// Reads `path` (a header, then rows of as many numbers); throws IoError naming the file, the line
// and what was expected.
StatsTable read_stats_table(const std::filesystem::path& path);

}  // namespace weft
