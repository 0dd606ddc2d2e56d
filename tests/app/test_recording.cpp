// What a headless run records for Blender and scripts: rest meshes and PC2 point caches (the
// default), the OBJ sequence, colliders.csv, recording.json, stats.csv and summary.json; the same
// output for the same scene whatever the thread count; a full disk stops cleanly.
#include <gtest/gtest.h>
#include <tiny_obj_loader.h>

#include <filesystem>
#include <fstream>

#include "io/point_cache.hpp"
#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string drape_scene = std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json";

std::vector<std::string> tiny_drape(const fs::path& out, int frames) {
  return {weft_program, "--headless",
          drape_scene,  "--out",
          out.string(), "--quiet",
          "--frames",   std::to_string(frames),
          "--set",      "cloths.0.grid.resolution=[9,7]",
          "--set",      "fps=24"};
}

std::vector<std::string> with(std::vector<std::string> command, const std::vector<std::string>& more) {
  command.insert(command.end(), more.begin(), more.end());
  return command;
}

TEST(Recording, DefaultIsARestMeshAndAPointCachePerCloth) {
  TempDir dir("weft_record_pc2");
  const fs::path out = dir.path() / "run";
  const auto result = run_program(with(tiny_drape(out, 6), {"--format", "both"}), dir.file("log.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;

  // The manifest names the files.
  const auto manifest = read_json(out / "recording.json");
  ASSERT_TRUE(manifest.is_object());
  EXPECT_EQ(manifest["format"], "weft-recording");
  EXPECT_EQ(manifest["version"], 1);
  EXPECT_EQ(manifest["fps"], 24.0);
  EXPECT_EQ(manifest["frames"], 6);
  ASSERT_EQ(manifest["cloths"].size(), 1u);
  EXPECT_EQ(manifest["cloths"][0]["rest_mesh"], "cloth.rest.obj");
  EXPECT_EQ(manifest["cloths"][0]["point_cache"], "cloth.pc2");
  EXPECT_EQ(manifest["colliders"][0]["type"], "sphere");
  EXPECT_EQ(manifest["colliders"][0]["radius"], 0.5);

  // The rest mesh reads as OBJ, with the cache's vertex count.
  tinyobj::ObjReader reader;
  ASSERT_TRUE(reader.ParseFromFile((out / "cloth.rest.obj").string()));
  EXPECT_EQ(reader.GetAttrib().vertices.size(), 3u * 63);

  // One sample per frame, each equal (to float precision) to that frame's OBJ.
  const PointCache cache = read_point_cache((out / "cloth.pc2").string());
  EXPECT_EQ(cache.num_points, 63);
  ASSERT_EQ(cache.samples.size(), 7u);
  for (int frame : {0, 3, 6}) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.obj", frame);
    tinyobj::ObjReader frame_reader;
    ASSERT_TRUE(frame_reader.ParseFromFile((out / name).string())) << name;
    const auto& v = frame_reader.GetAttrib().vertices;
    for (int i = 0; i < 63; ++i) {
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(cache.samples[frame](k, i), v[3 * i + k], 1e-6) << name;
    }
  }
  // The cloth fell between frame 0 and 6.
  EXPECT_LT(cache.samples[6].row(1).mean(), cache.samples[0].row(1).mean() - 0.05);

  // Colliders: a row per collider per frame.
  EXPECT_EQ(count_lines(out / "colliders.csv"), 1 + 7);
  std::ifstream colliders(out / "colliders.csv");
  std::string header, first;
  std::getline(colliders, header);
  std::getline(colliders, first);
  EXPECT_EQ(header, "frame,time,collider,type,x,y,z,qw,qx,qy,qz");
  EXPECT_EQ(first, "0,0,sphere,sphere,0,0,0,1,0,0,0");

  // Stats and summary.
  EXPECT_EQ(count_lines(out / "stats.csv"), 1 + 7);
  const auto summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["status"], "complete");
  EXPECT_EQ(summary["exit_code"], 0);
  EXPECT_EQ(summary["frames_written"], 7);
  EXPECT_NEAR(summary["simulated_seconds"].get<double>(), 6.0 / 24.0, 1e-12);
  EXPECT_GT(summary["energy"]["dissipated"].get<double>(), 0.0);
  EXPECT_FALSE(has_temporary_files(out));
}

TEST(Recording, FormatsWriteOnlyTheirFiles) {
  TempDir dir("weft_record_formats");
  ASSERT_EQ(run_program(tiny_drape(dir.path() / "pc2", 2), dir.file("a.txt")).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir.path() / "pc2" / "cloth.pc2"));
  EXPECT_FALSE(fs::exists(dir.path() / "pc2" / "frame_0000.obj"));
  ASSERT_EQ(
      run_program(with(tiny_drape(dir.path() / "obj", 2), {"--format", "obj"}), dir.file("b.txt")).exit_code,
      0);
  EXPECT_FALSE(fs::exists(dir.path() / "obj" / "cloth.pc2"));
  EXPECT_TRUE(fs::exists(dir.path() / "obj" / "frame_0002.obj"));
  EXPECT_TRUE(read_json(dir.path() / "obj" / "recording.json")["cloths"][0].count("point_cache") == 0);
  const auto bad =
      run_program(with(tiny_drape(dir.path() / "bad", 2), {"--format", "abc"}), dir.file("c.txt"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.error_text.find("--format"), std::string::npos) << bad.error_text;
}

// Same scene, same thread count: the same bytes. A different thread count gives the same bytes
// too today (docs/recording.md says why and what could change that).
TEST(Recording, OutputIsBitIdenticalAcrossRunsAndThreadCounts) {
  TempDir dir("weft_record_determinism");
  const std::vector<std::string> implicit = {
      "--format", "both", "--set", "solver.integrator=implicit_euler", "--set", "solver.time_step=0.01"};
  ASSERT_EQ(run_program(with(tiny_drape(dir.path() / "a", 8), with(implicit, {"--threads", "2"})),
                        dir.file("a.txt"))
                .exit_code,
            0);
  ASSERT_EQ(run_program(with(tiny_drape(dir.path() / "b", 8), with(implicit, {"--threads", "2"})),
                        dir.file("b.txt"))
                .exit_code,
            0);
  ASSERT_EQ(run_program(with(tiny_drape(dir.path() / "c", 8), with(implicit, {"--threads", "1"})),
                        dir.file("c.txt"))
                .exit_code,
            0);
  for (const std::string file : {"cloth.pc2", "frame_0008.obj", "frame_0004.obj", "colliders.csv"}) {
    const std::string a = read_bytes(dir.path() / "a" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, read_bytes(dir.path() / "b" / file)) << file << ": two runs with 2 threads differ";
    EXPECT_EQ(a, read_bytes(dir.path() / "c" / file)) << file << ": 1 and 2 threads differ";
  }
}

// A disk that fills up mid-run (here: a file size limit) stops with exit 4 naming the file; the
// point cache stays valid with every frame written so far, and no temporary is left behind.
TEST(Recording, FullDiskStopsCleanlyWithAValidCache) {
  TempDir dir("weft_record_full");
  const fs::path out = dir.path() / "run";
  std::string command = "trap '' XFSZ; ulimit -f 16; exec";
  for (const std::string& argument : tiny_drape(out, 400)) command += " '" + argument + "'";
  const auto result = run_program({"/bin/bash", "-c", command}, dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 4) << result.error_text;
  EXPECT_NE(result.error_text.find("cloth.pc2: cannot append frame"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("disk full?"), std::string::npos) << result.error_text;
  const auto run = read_json(out / "run.json");
  EXPECT_EQ(run["status"], "output_error");
  const PointCache cache = read_point_cache((out / "cloth.pc2").string());
  EXPECT_GT(cache.samples.size(), 10u);
  EXPECT_EQ(static_cast<int>(cache.samples.size()), run["frames_written"].get<int>());
  EXPECT_EQ(static_cast<long long>(fs::file_size(out / "cloth.pc2")),
            point_cache_size(63, static_cast<int>(cache.samples.size())));
  EXPECT_FALSE(has_temporary_files(out));
}

TEST(Recording, UnwritableOutputFolderLeavesNothing) {
  TempDir dir("weft_record_unwritable");
  const std::string blocker = dir.file("a_file");
  std::ofstream(blocker) << "not a folder";
  const auto result = run_program(tiny_drape(fs::path(blocker) / "out", 2), dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 4);
  EXPECT_NE(result.error_text.find("a_file/out: cannot create output folder"), std::string::npos)
      << result.error_text;
  EXPECT_FALSE(has_temporary_files(dir.path()));
}

}  // namespace
}  // namespace weft
