#pragma once
// A headless run's recording in its output folder, for Blender and for scripts:
//   point_cache (default): NAME.rest.obj (the mesh at frame 0) and NAME.pc2 (every frame) per
//     cloth, appended frame by frame;
//   obj_sequence: frame_0000.obj ... one file per frame, every cloth an `o` object;
//   both.
// Always: colliders.csv (each collider's placement per frame) and recording.json (the manifest
// naming these files, the frame rate and the colliders' shapes; tools/blender reads it).
#include <string>
#include <vector>

#include "io/csv_log.hpp"
#include "io/point_cache.hpp"
#include "sim/world.hpp"

namespace weft {

enum class RecordingFormat { point_cache, obj_sequence, both };
const char* to_string(RecordingFormat format);
// Parses "pc2", "obj" or "both"; returns false if unknown.
bool recording_format_from_string(const std::string& name, RecordingFormat& format);

inline constexpr int recording_manifest_version = 1;

class RecordingWriter {
 public:
  RecordingWriter(std::string dir, RecordingFormat format, int total_frames, double fps);

  // Starts a new recording of `world` (at frame 0): rest meshes, empty caches, manifest.
  void start(const World& world);
  // Continues a recording whose frames 0..last_frame are kept: cuts the caches and
  // colliders.csv back to them and removes later frame files.
  void resume(const World& world, int last_frame);
  // Records the world as frame `frame` (the next one). Throws IoError.
  void write_frame(int frame, const World& world);

  // Files written per frame that a resumed run must reproduce exactly (for tests and docs).
  std::string frame_file(int frame) const;
  const std::vector<std::string>& cache_files() const { return cache_files_; }

 private:
  void write_manifest(const World& world) const;
  void choose_file_names(const World& world);

  std::string dir_;
  RecordingFormat format_;
  int total_frames_;
  double fps_;
  std::vector<std::string> base_names_;   // per cloth: file name stem
  std::vector<std::string> cache_files_;  // per cloth: NAME.pc2 (point_cache, both)
  std::vector<PointCacheWriter> caches_;
  CsvLog collider_log_;                    // colliders.csv, a row per collider per frame
};

}  // namespace weft
