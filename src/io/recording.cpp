#include "io/recording.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "collision/collider_geometry.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/obj_io.hpp"

namespace weft {

namespace fs = std::filesystem;

namespace {

constexpr const char* manifest_file = "recording.json";
constexpr const char* collider_file = "colliders.csv";
constexpr const char* collider_header = "frame,time,collider,type,x,y,z,qw,qx,qy,qz";

// A name safe in a file name: letters, digits, '-', '_' and '.', anything else as '_'.
std::string file_stem(const std::string& name) {
  std::string stem;
  for (const char c : name) {
    const bool safe = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    stem += safe ? c : '_';
  }
  if (stem.empty() || stem[0] == '.') stem = "cloth" + stem;
  return stem;
}

std::vector<ObjObject> cloth_objects(const World& world) {
  std::vector<ObjObject> objects;
  for (const Cloth& cloth : world.cloths()) {
    objects.push_back({cloth.model.name, &cloth.state.x, &cloth.model.triangles, &cloth.model.uvs, true});
  }
  return objects;
}

nlohmann::json vec3_json(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

// The frame index in "frame_0012.obj", or -1 for any other name.
int frame_of_file_name(const std::string& name) {
  if (name.size() < 11 || name.rfind("frame_", 0) != 0 || name.substr(name.size() - 4) != ".obj") return -1;
  const std::string digits = name.substr(6, name.size() - 10);
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(digits);
}

// A CSV field: quoted (quotes doubled) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

const char* to_string(RecordingFormat format) {
  switch (format) {
    case RecordingFormat::point_cache:
      return "pc2";
    case RecordingFormat::obj_sequence:
      return "obj";
    case RecordingFormat::both:
      return "both";
  }
  return "?";
}

bool recording_format_from_string(const std::string& name, RecordingFormat& format) {
  for (const RecordingFormat candidate :
       {RecordingFormat::point_cache, RecordingFormat::obj_sequence, RecordingFormat::both}) {
    if (name == to_string(candidate)) {
      format = candidate;
      return true;
    }
  }
  return false;
}

RecordingWriter::RecordingWriter(std::string dir, RecordingFormat format, int total_frames, double fps)
    : dir_(std::move(dir)), format_(format), total_frames_(total_frames), fps_(fps) {}

std::string RecordingWriter::frame_file(int frame) const {
  const int digits = std::max(4, static_cast<int>(std::to_string(total_frames_).size()));
  std::ostringstream name;
  name << "frame_" << std::setw(digits) << std::setfill('0') << frame << ".obj";
  return name.str();
}

void RecordingWriter::choose_file_names(const World& world) {
  base_names_.clear();
  cache_files_.clear();
  std::set<std::string> taken;
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    std::string stem = file_stem(world.cloths()[c].model.name);
    if (taken.count(stem)) stem += "_" + std::to_string(c);
    taken.insert(stem);
    base_names_.push_back(stem);
    if (format_ != RecordingFormat::obj_sequence) cache_files_.push_back(stem + ".pc2");
  }
}

void RecordingWriter::write_manifest(const World& world) const {
  nlohmann::json cloths = nlohmann::json::array();
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    const Cloth& cloth = world.cloths()[c];
    nlohmann::json entry = {{"name", cloth.model.name},
                            {"vertices", cloth.num_vertices()},
                            {"triangles", cloth.model.triangles.cols()}};
    if (format_ != RecordingFormat::obj_sequence) {
      entry["rest_mesh"] = base_names_[c] + ".rest.obj";
      entry["point_cache"] = cache_files_[c];
    }
    cloths.push_back(entry);
  }
  nlohmann::json colliders = nlohmann::json::array();
  for (const Collider& collider : world.colliders()) {
    nlohmann::json entry = {{"name", collider.name}, {"type", to_string(collider.shape)}};
    switch (collider.shape) {
      case ColliderShape::plane:
        entry["normal"] = vec3_json(collider.normal);
        break;
      case ColliderShape::sphere:
        entry["radius"] = collider.radius;
        break;
      case ColliderShape::box:
        entry["half_extents"] = vec3_json(collider.half_extents);
        break;
      case ColliderShape::capsule:
      case ColliderShape::cylinder:
      case ColliderShape::mesh: {
        // The triangles the collision pipeline uses, around the centre (colliders.csv places them).
        const TriangleMesh surface = collider_surface(collider);
        nlohmann::json vertices = nlohmann::json::array();
        for (int v = 0; v < surface.num_vertices(); ++v) {
          vertices.push_back(vec3_json(Vec3(surface.positions.col(v) - collider.center)));
        }
        nlohmann::json triangles = nlohmann::json::array();
        for (int t = 0; t < surface.num_triangles(); ++t) {
          triangles.push_back({surface.triangles(0, t), surface.triangles(1, t), surface.triangles(2, t)});
        }
        entry["vertices"] = std::move(vertices);
        entry["triangles"] = std::move(triangles);
        break;
      }
    }
    colliders.push_back(entry);
  }
  const nlohmann::json manifest = {
      {"format", "weft-recording"},
      {"version", recording_manifest_version},
      {"up_axis", "+y"},
      {"units", "m"},
      {"fps", fps_},
      {"frames", total_frames_},
      {"frame_files",
       format_ == RecordingFormat::point_cache ? nlohmann::json(nullptr) : nlohmann::json(frame_file(0))},
      {"cloths", cloths},
      {"collider_transforms", collider_file},
      {"colliders", colliders}};
  write_file_atomically((fs::path(dir_) / manifest_file).string(),
                        [&](std::ostream& out) { out << manifest.dump(2) << '\n'; });
}

void RecordingWriter::start(const World& world) {
  choose_file_names(world);
  caches_.clear();
  collider_log_ = CsvLog::create((fs::path(dir_) / collider_file).string(), collider_header);
  if (format_ != RecordingFormat::obj_sequence) {
    for (size_t c = 0; c < world.cloths().size(); ++c) {
      const Cloth& cloth = world.cloths()[c];
      const std::string rest_path = (fs::path(dir_) / (base_names_[c] + ".rest.obj")).string();
      write_file_atomically(rest_path, [&](std::ostream& out) {
        write_obj(out, {{cloth.model.name, &cloth.state.x, &cloth.model.triangles, &cloth.model.uvs, true}});
      });
      caches_.push_back(
          PointCacheWriter::create((fs::path(dir_) / cache_files_[c]).string(), cloth.num_vertices()));
    }
  }
  write_manifest(world);
}

void RecordingWriter::resume(const World& world, int last_frame) {
  choose_file_names(world);
  caches_.clear();
  for (size_t c = 0; c < cache_files_.size(); ++c) {
    caches_.push_back(PointCacheWriter::reopen((fs::path(dir_) / cache_files_[c]).string(),
                                               world.cloths()[c].num_vertices(), last_frame + 1));
  }
  // Frames after the checkpoint are recomputed: drop their files and collider rows, and the
  // temporaries of atomic writes that a killed run left behind ("NAME.tmp.PID").
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir_, error)) {
    const std::string name = entry.path().filename().string();
    if (frame_of_file_name(name) > last_frame || name.find(".tmp.") != std::string::npos)
      fs::remove(entry.path(), error);
  }
  collider_log_ = CsvLog::reopen((fs::path(dir_) / collider_file).string(), collider_header, last_frame);
  write_manifest(world);
}

void RecordingWriter::write_frame(int frame, const World& world) {
  if (format_ != RecordingFormat::point_cache) {
    const std::vector<ObjObject> objects = cloth_objects(world);
    write_file_atomically((fs::path(dir_) / frame_file(frame)).string(),
                          [&](std::ostream& out) { write_obj(out, objects); });
  }
  for (size_t c = 0; c < caches_.size(); ++c) caches_[c].append(world.cloths()[c].state.x);

  // Collider placement at this frame's time: where the centre is and the rotation from time 0.
  for (const Collider& collider : world.colliders()) {
    const Mat3 rotation = collider.motion.rotation(world.time());
    const Vec3 location = collider.motion.place(collider.center, world.time());
    const Eigen::Quaterniond q(rotation);
    std::ostringstream row;
    row << std::setprecision(17) << frame << ',' << world.time() << ',' << csv_field(collider.name) << ','
        << to_string(collider.shape) << ',' << location.x() << ',' << location.y() << ',' << location.z() << ','
        << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z();
    collider_log_.append(row.str());
  }
}

}  // namespace weft
