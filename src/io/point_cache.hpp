#pragma once
// Point caches in the PC2 format that Blender's Mesh Cache modifier reads: one file per object,
// a 32-byte header then one sample (every point's x, y, z as 32-bit floats) per frame, all
// little-endian:
//   char[12] "POINTCACHE2\0"  int32 version (1)  int32 point count
//   float32 start frame  float32 sample rate (frames between samples)  int32 sample count
// The writer appends a sample, then updates the count in the header, so a run killed at any
// moment leaves a valid cache of the frames completed (at worst with unused bytes at the end).
#include <iosfwd>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace weft {

class PointCacheWriter {
 public:
  PointCacheWriter() = default;
  PointCacheWriter(PointCacheWriter&& other) noexcept;
  PointCacheWriter& operator=(PointCacheWriter&& other) noexcept;
  PointCacheWriter(const PointCacheWriter&) = delete;
  PointCacheWriter& operator=(const PointCacheWriter&) = delete;
  ~PointCacheWriter();

  // Creates `path` (replacing any file there) holding a header and no samples. Throws IoError.
  static PointCacheWriter create(const std::string& path, int num_points, float start_frame = 0.0f,
                                 float sample_rate = 1.0f);
  // Opens an existing cache to continue after its first `keep_samples` samples (resuming a run):
  // checks the header and point count and cuts everything after those samples. Throws IoError.
  static PointCacheWriter reopen(const std::string& path, int num_points, int keep_samples);

  // Appends one sample (3 x num_points) and updates the header. On failure (disk full) the file
  // is cut back to its previous samples and IoError names the file and the cause.
  void append(const Positions& positions);

  int samples() const { return samples_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  int num_points_ = 0;
  int samples_ = 0;
  std::vector<float> buffer_;
};

struct PointCache {
  int num_points = 0;
  float start_frame = 0.0f;
  float sample_rate = 1.0f;
  std::vector<Eigen::Matrix3Xf> samples;  // each 3 x num_points
};

// Reads a whole cache (the samples its header counts). Throws IoError naming the file and the
// field that is wrong (magic, version, counts, a file shorter than its header says).
PointCache read_point_cache(const std::string& path);

// The same from a stream holding a cache's bytes; `path` names it in errors (read_point_cache
// opens the file and calls this).
PointCache read_point_cache(std::istream& in, const std::string& path);

// The samples a cache's header counts, without reading them; throws IoError like
// read_point_cache, also when the file is shorter than those samples.
int point_cache_samples(const std::string& path);

// Bytes of a cache with `samples` samples of `num_points` points.
long long point_cache_size(int num_points, int samples);

}  // namespace weft
