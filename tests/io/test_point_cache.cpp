// PC2 point caches: what is written reads back, the header always counts whole samples (a run
// killed mid-append leaves a valid cache), resuming cuts the cache back, bad files are named.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/point_cache.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

Positions sample(int points, double offset) {
  Positions x(3, points);
  for (int i = 0; i < points; ++i) x.col(i) = Vec3(i + offset, 2.0 * i - offset, 0.25 * offset);
  return x;
}

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const IoError& error) {
    return error.what();
  }
  return "";
}

TEST(PointCache, WritesAHeaderAndSamplesThatReadBack) {
  TempDir dir("weft_pc2");
  const std::string path = dir.file("cloth.pc2");
  {
    PointCacheWriter writer = PointCacheWriter::create(path, 5, 0.0f, 1.0f);
    EXPECT_EQ(point_cache_size(5, 0), static_cast<long long>(fs::file_size(path)));
    for (int s = 0; s < 3; ++s) writer.append(sample(5, s));
    EXPECT_EQ(writer.samples(), 3);
  }
  EXPECT_EQ(static_cast<long long>(fs::file_size(path)), 32 + 3 * 5 * 12);
  // The header as Blender reads it.
  std::ifstream in(path, std::ios::binary);
  char magic[12];
  int32_t version, points, samples;
  float start, rate;
  in.read(magic, 12).read(reinterpret_cast<char*>(&version), 4).read(reinterpret_cast<char*>(&points), 4);
  in.read(reinterpret_cast<char*>(&start), 4).read(reinterpret_cast<char*>(&rate), 4);
  in.read(reinterpret_cast<char*>(&samples), 4);
  EXPECT_EQ(std::string(magic, 12), std::string("POINTCACHE2\0", 12));
  EXPECT_EQ(version, 1);
  EXPECT_EQ(points, 5);
  EXPECT_EQ(start, 0.0f);
  EXPECT_EQ(rate, 1.0f);
  EXPECT_EQ(samples, 3);

  const PointCache cache = read_point_cache(path);
  ASSERT_EQ(cache.samples.size(), 3u);
  for (int s = 0; s < 3; ++s) EXPECT_EQ(cache.samples[s], sample(5, s).cast<float>()) << s;
}

TEST(PointCache, BytesPastTheCountedSamplesAreIgnored) {
  // A run killed between writing a sample and updating the count leaves extra bytes at the end.
  TempDir dir("weft_pc2_killed");
  const std::string path = dir.file("cloth.pc2");
  {
    PointCacheWriter writer = PointCacheWriter::create(path, 4);
    writer.append(sample(4, 0));
    writer.append(sample(4, 1));
  }
  std::ofstream(path, std::ios::binary | std::ios::app) << std::string(20, '\x7f');
  const PointCache cache = read_point_cache(path);
  ASSERT_EQ(cache.samples.size(), 2u);
  EXPECT_EQ(cache.samples[1], sample(4, 1).cast<float>());
}

TEST(PointCache, SampleCountIsReadFromTheHeaderAndCheckedAgainstTheSize) {
  TempDir dir("weft_pc2_count");
  const std::string path = dir.file("cloth.pc2");
  {
    PointCacheWriter writer = PointCacheWriter::create(path, 4);
    for (int s = 0; s < 3; ++s) writer.append(sample(4, s));
  }
  EXPECT_EQ(point_cache_samples(path), 3);
  std::filesystem::resize_file(path, point_cache_size(4, 3) - 1);
  EXPECT_THROW(point_cache_samples(path), IoError);
  EXPECT_THROW(point_cache_samples(dir.file("none.pc2")), IoError);
}

TEST(PointCache, ReopenKeepsTheFirstSamplesAndContinues) {
  TempDir dir("weft_pc2_resume");
  const std::string path = dir.file("cloth.pc2");
  {
    PointCacheWriter writer = PointCacheWriter::create(path, 3);
    for (int s = 0; s < 4; ++s) writer.append(sample(3, s));
  }
  {
    PointCacheWriter writer = PointCacheWriter::reopen(path, 3, 2);
    EXPECT_EQ(writer.samples(), 2);
    writer.append(sample(3, 10));
  }
  const PointCache cache = read_point_cache(path);
  ASSERT_EQ(cache.samples.size(), 3u);
  EXPECT_EQ(cache.samples[1], sample(3, 1).cast<float>());
  EXPECT_EQ(cache.samples[2], sample(3, 10).cast<float>());
  EXPECT_EQ(static_cast<long long>(fs::file_size(path)), point_cache_size(3, 3));

  EXPECT_NE(error_of([&] { PointCacheWriter::reopen(path, 4, 1); }).find("point count: expected 4, got 3"),
            std::string::npos);
  EXPECT_NE(error_of([&] { PointCacheWriter::reopen(path, 3, 9); }).find("sample count: expected at least 9"),
            std::string::npos);
}

TEST(PointCache, BadFilesAreNamedWithWhatIsWrong) {
  TempDir dir("weft_pc2_bad");
  const std::string not_cache = dir.file("not.pc2");
  std::ofstream(not_cache) << "POINTCACHE3 and then some more bytes to pass 32";
  EXPECT_NE(error_of([&] { read_point_cache(not_cache); }).find("not.pc2: not a PC2 point cache"),
            std::string::npos);

  const std::string short_file = dir.file("short.pc2");
  {
    PointCacheWriter writer = PointCacheWriter::create(short_file, 10);
    writer.append(sample(10, 0));
    writer.append(sample(10, 1));
  }
  fs::resize_file(short_file, point_cache_size(10, 1) + 7);
  const std::string message = error_of([&] { read_point_cache(short_file); });
  EXPECT_NE(message.find("short.pc2: PC2 sample count: the header says 2 samples, the file holds 1"),
            std::string::npos)
      << message;

  EXPECT_NE(error_of([&] { read_point_cache(dir.file("missing.pc2")); }).find("missing.pc2"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              PointCacheWriter::create(dir.file("no/such/folder/x.pc2"), 3);
            }).find("x.pc2: cannot create"),
            std::string::npos);
}

// Found by tests/fuzz/fuzz_point_cache: a 39-byte file whose header counts 2^31 - 1 samples must
// not make the reader allocate them (out of memory) before it finds the file short. The counts
// are checked against the file's size first, by division, as 12 * points * samples overflows.
TEST(PointCache, CountsBeyondTheFileAreRefusedBeforeAnythingIsAllocated) {
  TempDir dir("weft_pc2_counts");
  const auto header_only = [&](const std::string& name, int32_t points, int32_t samples) {
    std::string bytes("POINTCACHE2\0", 12);
    const int32_t version = 1;
    const float start = 0.0f, rate = 1.0f;
    bytes.append(reinterpret_cast<const char*>(&version), 4);
    bytes.append(reinterpret_cast<const char*>(&points), 4);
    bytes.append(reinterpret_cast<const char*>(&start), 4);
    bytes.append(reinterpret_cast<const char*>(&rate), 4);
    bytes.append(reinterpret_cast<const char*>(&samples), 4);
    bytes += std::string(7, '\x2d');
    std::ofstream(dir.file(name), std::ios::binary) << bytes;
    return dir.file(name);
  };
  const std::string many = header_only("many.pc2", 1 << 30, 2147483647);
  EXPECT_NE(error_of([&] {
              read_point_cache(many);
            }).find("many.pc2: PC2 sample count: the header says 2147483647 samples, the file holds 0"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              point_cache_samples(many);
            }).find("the header says 2147483647 samples, the file holds 0"),
            std::string::npos);
  const std::string empty = header_only("empty.pc2", 0, 2147483647);
  EXPECT_NE(error_of([&] {
              read_point_cache(empty);
            }).find("empty.pc2: PC2 point count: the header says 2147483647 samples of 0 points"),
            std::string::npos);
}

TEST(PointCache, AppendRejectsASampleOfTheWrongSize) {
  TempDir dir("weft_pc2_size");
  PointCacheWriter writer = PointCacheWriter::create(dir.file("c.pc2"), 3);
  EXPECT_NE(error_of([&] { writer.append(sample(4, 0)); }).find("sample has 4 points"), std::string::npos);
  EXPECT_EQ(writer.samples(), 0);
}

}  // namespace
}  // namespace weft
