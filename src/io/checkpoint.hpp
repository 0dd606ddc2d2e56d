#pragma once
// Checkpoints: the full state of a run at a frame boundary, so a killed run can resume and
// produce exactly the frames an uninterrupted run would have.
//
// File layout (little-endian), version 4:
//   char[8] "WEFTCKPT"  uint32 version  uint32 reserved (0)  uint64 payload bytes
//   payload                                          (below)
//   uint64 FNV-1a 64-bit hash of the payload
// payload: string resolved scene JSON, int32 frame, float64 time, float64 initial energy,
//   uint32 cloth count, per cloth: string name, matrix x, matrix v, matrix rest_positions,
//     float64 adaptive next_step, int32 accepted, int32 rejected, float64 last_error,
//     matrix membrane rest (5 x n_triangles: dm_inverse column-major, area; 0 columns when the
//     membrane is off);
//   uint32 collider count, per collider: string name, vec3 center, vec3 normal, float64 radius,
//     vec3 half_extents;
//   uint64 contact pair count, per pair int32 kind, a, b (World::contact_history: the last
//     step's proximity pairs, which the contact penalty of the next step reads);
//   float64 x 6 energy flows since frame 0 (external work, damping, integrator, contact,
//     plastic, residual: sim/energy_ledger.hpp).
// string: uint64 length + bytes; matrix: uint64 rows, uint64 cols, rows*cols float64 column-major.
// Scripted pins need nothing: they follow from the time. Version 4 files (five flows, before the
// residual flow) are read with a residual of zero. Version 3 files (no energy flows) are
// read with flows of zero, so a resumed run's budget_error carries the flows of the frames
// before it; version 2 files (no contact pairs) are read with none; version 1 files (no membrane rest) are refused with the version they hold.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "physics/adaptive_stepping.hpp"
#include "sim/world.hpp"

namespace weft {

inline constexpr unsigned checkpoint_version = 5;

struct ClothCheckpoint {
  std::string name;
  Positions x;               // (3 x n_vertices)
  Positions v;               // (3 x n_vertices)
  Positions rest_positions;  // (3 x n_vertices)
  AdaptiveState adaptive;
  Eigen::MatrixXd membrane_rest;  // (5 x n_triangles): dm_inverse (column-major) and area,
                                  // which plastic flow changes; 0 columns without a membrane
};

struct ColliderCheckpoint {
  std::string name;
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();
  double radius = 0.0;
  Vec3 half_extents = Vec3::Zero();
};

struct Checkpoint {
  std::string scene_json;       // the resolved scene the run was started with
  int frame = 0;                // the last frame written before this checkpoint
  double time = 0.0;            // s, the world's time at that frame
  double initial_energy = 0.0;  // J, total energy at frame 0 (stats.csv's energy_dissipated)
  std::vector<ClothCheckpoint> cloths;
  std::vector<ColliderCheckpoint> colliders;
  std::vector<std::array<int, 3>> contact_pairs;  // World::contact_history()
  EnergyFlows energy_flows;     // J, summed from frame 0 to `frame` (stats.csv's budget columns)
};

Checkpoint capture_checkpoint(const World& world, int frame, const std::string& scene_json,
                              double initial_energy, const EnergyFlows& energy_flows = {});

// Puts the checkpoint's state into a world built from the same scene. Throws IoError naming
// `file` when the world does not match (cloth or collider count, names, vertex counts).
void restore_checkpoint(const Checkpoint& checkpoint, World& world, const std::string& file);

// Writes atomically (temporary file, then rename). Throws IoError.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Reads and verifies magic, version, size and checksum. Throws IoError naming the file and
// what is wrong with it.
Checkpoint read_checkpoint(const std::string& path);

// The same from a checkpoint file's bytes; `path` names it in errors (read_checkpoint reads the
// file and calls this).
Checkpoint parse_checkpoint(const std::string& file, const std::string& path);

// The checksum a checkpoint file ends with: FNV-1a (64 bits) of its payload's bytes.
uint64_t checkpoint_checksum(const std::string& payload);

}  // namespace weft
