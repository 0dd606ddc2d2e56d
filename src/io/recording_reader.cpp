#include "io/recording_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <utility>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "collision/collider_geometry.hpp"
#include "core/error.hpp"
#include "io/obj_io.hpp"
#include "io/scene_file.hpp"

namespace weft {

namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path, const char* what) {
  std::ifstream in(path);
  if (!in) throw IoError(path.string() + ": cannot open; expected " + what);
  const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
  if (document.is_discarded() || !document.is_object()) {
    throw IoError(path.string() + ": expected a JSON object (" + what + ")");
  }
  return document;
}

template <typename T>
T field(const nlohmann::json& object, const char* key, const fs::path& file, const char* expected) {
  if (!object.contains(key))
    throw IoError(file.string() + ": \"" + key + "\" is missing; expected " + expected);
  try {
    return object.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw IoError(file.string() + ": \"" + key + "\": expected " + expected);
  }
}

// run.json: the scene's colliders.
void read_run(Recording& recording) {
  const fs::path path = recording.dir / "run.json";
  const nlohmann::json run = read_json(path, "the run.json of a headless recording");
  if (!run.contains("scene") || !run["scene"].is_object()) {
    throw IoError(path.string() + ": \"scene\": expected the resolved scene as a JSON object");
  }
  SceneDesc scene;
  try {
    scene = parse_scene(run["scene"], path.string() + " (scene)");
  } catch (const SceneError& error) {
    throw IoError(error.what());
  }
  recording.fps = scene.fps;
  recording.scene = scene;
  for (const Collider& collider : scene.colliders) recording.colliders.push_back({collider, {}});
}

// recording.json: the cloths' files and the mesh colliders' triangles.
void read_manifest(Recording& recording) {
  const fs::path path = recording.dir / "recording.json";
  const nlohmann::json manifest = read_json(path, "the recording.json manifest of a headless recording");
  const auto cloths = field<std::vector<nlohmann::json>>(manifest, "cloths", path, "an array of cloths");
  const auto colliders =
      field<std::vector<nlohmann::json>>(manifest, "colliders", path, "an array of colliders");
  if (colliders.size() != recording.colliders.size()) {
    throw IoError(path.string() + ": \"colliders\": expected " + std::to_string(recording.colliders.size()) +
                  " colliders, as run.json's scene has, found " + std::to_string(colliders.size()));
  }
  const nlohmann::json frame_files = manifest.value("frame_files", nlohmann::json(nullptr));
  if (frame_files.is_string()) {
    // "frame_0000.obj": the digits' count says how frame files are named.
    const std::string first = frame_files.get<std::string>();
    const size_t digits = first.size() - std::string("frame_.obj").size();
    recording.frame_file_pattern = "frame_%0" + std::to_string(digits) + "d.obj";
  }
  for (const nlohmann::json& entry : cloths) {
    RecordedCloth cloth;
    cloth.name = field<std::string>(entry, "name", path, "a cloth's name");
    cloth.vertices = field<int>(entry, "vertices", path, "a cloth's vertex count");
    if (entry.contains("point_cache")) {
      const fs::path rest = recording.dir / field<std::string>(entry, "rest_mesh", path, "a rest mesh file");
      const fs::path cache = recording.dir / field<std::string>(entry, "point_cache", path, "a PC2 file");
      const TriangleMesh mesh = read_obj(rest.string());
      if (mesh.num_vertices() != cloth.vertices) {
        throw IoError(rest.string() + ": expected " + std::to_string(cloth.vertices) +
                      " vertices (recording.json), found " + std::to_string(mesh.num_vertices()));
      }
      cloth.triangles = mesh.triangles;
      cloth.cache = read_point_cache(cache.string());
      if (cloth.cache.num_points != cloth.vertices) {
        throw IoError(cache.string() + ": expected " + std::to_string(cloth.vertices) +
                      " points (recording.json), found " + std::to_string(cloth.cache.num_points));
      }
    } else if (recording.frame_file_pattern.empty()) {
      throw IoError(path.string() + ": cloth \"" + cloth.name +
                    "\": expected a \"point_cache\", or \"frame_files\" naming OBJ frames");
    }
    recording.cloths.push_back(std::move(cloth));
  }
  for (size_t k = 0; k < colliders.size(); ++k) {
    RecordedCollider& recorded = recording.colliders[k];
    if (recorded.collider.shape != ColliderShape::mesh) {
      recorded.surface = collider_surface(recorded.collider);
      continue;
    }
    // A mesh collider's triangles, around its centre, as the pipeline used them.
    const auto vertices = field<std::vector<std::vector<double>>>(colliders[k], "vertices", path,
                                                                  "a mesh collider's vertices as [x, y, z]");
    const auto triangles = field<std::vector<std::vector<int>>>(colliders[k], "triangles", path,
                                                                "a mesh collider's triangles as [a, b, c]");
    recorded.surface.positions.resize(3, static_cast<Eigen::Index>(vertices.size()));
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (vertices[v].size() != 3) throw IoError(path.string() + ": \"vertices\": expected [x, y, z]");
      recorded.surface.positions.col(v) =
          Vec3(vertices[v][0], vertices[v][1], vertices[v][2]) + recorded.collider.center;
    }
    recorded.surface.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
    for (size_t t = 0; t < triangles.size(); ++t) {
      if (triangles[t].size() != 3) throw IoError(path.string() + ": \"triangles\": expected [a, b, c]");
      for (int c = 0; c < 3; ++c) {
        if (triangles[t][c] < 0 || triangles[t][c] >= static_cast<int>(vertices.size())) {
          throw IoError(path.string() + ": \"triangles\": expected vertex indices below " +
                        std::to_string(vertices.size()));
        }
        recorded.surface.triangles(c, t) = triangles[t][c];
      }
    }
  }
}

// The frames every cloth has: the fewest samples of a cache (a run killed mid-frame leaves some
// caches a sample ahead of others), or the OBJ frame files from frame_0000.obj on.
void count_frames(Recording& recording) {
  const fs::path manifest = recording.dir / "recording.json";
  if (recording.cloths.empty())
    throw IoError(manifest.string() + ": \"cloths\": expected at least one cloth");
  if (recording.cloths.front().cache.samples.empty() && !recording.frame_file_pattern.empty()) {
    char name[64];
    for (;; ++recording.frames) {
      std::snprintf(name, sizeof name, recording.frame_file_pattern.c_str(), recording.frames);
      if (!fs::exists(recording.dir / name)) break;
    }
  } else {
    recording.frames = static_cast<int>(recording.cloths.front().cache.samples.size());
    for (const RecordedCloth& cloth : recording.cloths) {
      recording.frames = std::min(recording.frames, static_cast<int>(cloth.cache.samples.size()));
    }
  }
  if (recording.frames == 0) {
    throw IoError(manifest.string() +
                  ": expected at least frame 0 in the point caches or frame files, found none");
  }
}

// colliders.csv: a row per collider per frame, in frame order and the scene's collider order.
void read_placements(Recording& recording) {
  const fs::path path = recording.dir / "colliders.csv";
  std::ifstream in(path);
  if (!in) throw IoError(path.string() + ": cannot open; expected each collider's placement per frame");
  std::string line;
  std::getline(in, line);
  if (line != "frame,time,collider,type,x,y,z,qw,qx,qy,qz") {
    throw IoError(path.string() + ": expected the header frame,time,collider,type,x,y,z,qw,qx,qy,qz");
  }
  const size_t num_colliders = recording.colliders.size();
  recording.placements.assign(recording.frames, std::vector<Placement>(num_colliders));
  for (int frame = 0; frame < recording.frames; ++frame) {
    for (size_t k = 0; k < num_colliders; ++k) {
      const std::string where = path.string() + ": row of frame " + std::to_string(frame) + ", collider \"" +
                                recording.colliders[k].collider.name + "\"";
      if (!std::getline(in, line)) throw IoError(where + ": missing (the file ends early)");
      // The name may hold commas (quoted): the frame is the first field, the 7 numbers the last.
      const size_t first_comma = line.find(',');
      std::vector<double> numbers;
      size_t end = line.size();
      for (int n = 0; n < 7; ++n) {
        const size_t comma = line.rfind(',', end - 1);
        if (comma == std::string::npos || comma < first_comma) break;
        numbers.insert(numbers.begin(), std::strtod(line.c_str() + comma + 1, nullptr));
        end = comma;
      }
      if (first_comma == std::string::npos || numbers.size() != 7 ||
          std::atoi(line.substr(0, first_comma).c_str()) != frame) {
        throw IoError(where + ": expected frame,time,collider,type,x,y,z,qw,qx,qy,qz");
      }
      const Vec3 location(numbers[0], numbers[1], numbers[2]);
      const Eigen::Quaterniond q(numbers[3], numbers[4], numbers[5], numbers[6]);
      if (!location.allFinite() || !std::isfinite(q.norm()) || std::abs(q.norm() - 1.0) > 1e-6) {
        throw IoError(where + ": expected a finite location and a unit quaternion");
      }
      Placement& placement = recording.placements[frame][k];
      placement.rotation = q.toRotationMatrix();
      placement.translation = location - placement.rotation * recording.colliders[k].collider.center;
    }
  }
}

}  // namespace

Recording read_recording(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) {
    throw IoError(dir.string() +
                  ": no such folder; expected a headless recording (weft --headless SCENE --out DIR)");
  }
  Recording recording;
  recording.dir = dir;
  read_run(recording);
  read_manifest(recording);
  count_frames(recording);
  read_placements(recording);
  return recording;
}

std::vector<Positions> cloth_positions(Recording& recording, int frame) {
  namespace fs = std::filesystem;
  std::vector<Positions> positions(recording.cloths.size());
  if (!recording.cloths.empty() && recording.cloths.front().cache.samples.empty()) {
    char name[64];
    std::snprintf(name, sizeof name, recording.frame_file_pattern.c_str(), frame);
    const fs::path file = recording.dir / name;
    const TriangleMesh mesh = read_obj(file.string());
    // The cloths one after the other, in the scene's order.
    int first_vertex = 0, first_triangle = 0;
    for (size_t c = 0; c < recording.cloths.size(); ++c) {
      RecordedCloth& cloth = recording.cloths[c];
      const int triangles = cloth.triangles.cols() > 0 ? static_cast<int>(cloth.triangles.cols()) : -1;
      if (first_vertex + cloth.vertices > mesh.num_vertices()) {
        throw IoError(file.string() + ": expected the vertices of every cloth (recording.json), found " +
                      std::to_string(mesh.num_vertices()));
      }
      positions[c] = mesh.positions.middleCols(first_vertex, cloth.vertices);
      if (frame == 0 && triangles < 0) {
        // Each cloth's triangles: the run of the file's triangles whose corners are its vertices.
        int last = first_triangle;
        while (last < mesh.num_triangles() && mesh.triangles.col(last).minCoeff() >= first_vertex &&
               mesh.triangles.col(last).maxCoeff() < first_vertex + cloth.vertices) {
          ++last;
        }
        cloth.triangles =
            mesh.triangles.middleCols(first_triangle, last - first_triangle).array() - first_vertex;
      }
      first_vertex += cloth.vertices;
      first_triangle += static_cast<int>(cloth.triangles.cols());
    }
    return positions;
  }
  for (size_t c = 0; c < recording.cloths.size(); ++c) {
    positions[c] = recording.cloths[c].cache.samples[frame].cast<double>();
  }
  return positions;
}

int StatsTable::column(const std::string& name) const {
  for (size_t k = 0; k < columns.size(); ++k) {
    if (columns[k] == name) return static_cast<int>(k);
  }
  return -1;
}

StatsTable read_stats_table(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path.string() + ": cannot open; expected the run's stats.csv");
  StatsTable table;
  std::string line;
  if (!std::getline(in, line) || line.rfind("frame,", 0) != 0)
    throw IoError(path.string() + ": line 1: expected a header starting with frame,");
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    table.columns.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<double> row;
    const char* cursor = line.c_str();
    for (size_t k = 0; k < table.columns.size(); ++k) {
      char* end = nullptr;
      row.push_back(std::strtod(cursor, &end));
      const bool last = k + 1 == table.columns.size();
      if (end == cursor || (last ? *end != '\0' : *end != ',')) {
        throw IoError(path.string() + ": line " + std::to_string(number) + ": expected " +
                      std::to_string(table.columns.size()) + " numbers separated by commas (column \"" +
                      table.columns[k] + "\")");
      }
      cursor = end + (last ? 0 : 1);
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace weft
