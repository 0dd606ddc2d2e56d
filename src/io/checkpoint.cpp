#include "io/checkpoint.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "checkpoint.cpp writes in host byte order, which must be little-endian"
#endif

namespace weft {

namespace {

constexpr char magic[8] = {'W', 'E', 'F', 'T', 'C', 'K', 'P', 'T'};
constexpr size_t header_bytes = 8 + 4 + 4 + 8;

// Appends plain values to a byte string.
class PayloadWriter {
 public:
  template <typename T>
  void value(T v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void string(const std::string& text) {
    value<uint64_t>(text.size());
    bytes_ += text;
  }
  void vec3(const Vec3& v) {
    for (int i = 0; i < 3; ++i) value<double>(v[i]);
  }
  void matrix(const Eigen::MatrixXd& m) {
    value<uint64_t>(m.rows());
    value<uint64_t>(m.cols());
    bytes_.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * m.size());
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

// Reads them back, failing with the file's name and the field being read when it runs out.
class PayloadReader {
 public:
  PayloadReader(const std::string& bytes, const std::string& file) : bytes_(bytes), file_(file) {}

  template <typename T>
  T value(const char* field) {
    T v;
    take(&v, sizeof v, field);
    return v;
  }
  std::string string(const char* field) {
    const uint64_t size = value<uint64_t>(field);
    if (size > bytes_.size() - offset_) fail(field);
    std::string text = bytes_.substr(offset_, size);
    offset_ += size;
    return text;
  }
  Vec3 vec3(const char* field) {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = value<double>(field);
    return v;
  }
  Positions positions(const char* field) { return matrix(3, field); }
  Eigen::MatrixXd matrix(uint64_t expected_rows, const char* field) {
    const uint64_t rows = value<uint64_t>(field), cols = value<uint64_t>(field);
    if (rows != expected_rows || cols > (bytes_.size() - offset_) / (rows * sizeof(double))) fail(field);
    Eigen::MatrixXd m(rows, static_cast<Eigen::Index>(cols));
    take(m.data(), sizeof(double) * m.size(), field);
    return m;
  }
  bool at_end() const { return offset_ == bytes_.size(); }

 private:
  [[noreturn]] void fail(const char* field) const {
    throw IoError(file_ + ": checkpoint field " + field + ": malformed or cut short");
  }
  void take(void* out, size_t size, const char* field) {
    if (size > bytes_.size() - offset_) fail(field);
    if (size == 0) return;  // an empty matrix's data() is null, which memcpy must not be given
    std::memcpy(out, bytes_.data() + offset_, size);
    offset_ += size;
  }

  const std::string& bytes_;
  const std::string& file_;
  size_t offset_ = 0;
};

// Membrane rest shapes as columns (dm_inverse column-major, area) and back.
Eigen::MatrixXd pack_membrane_rest(const std::vector<MembraneRest>& rest) {
  Eigen::MatrixXd packed(5, static_cast<Eigen::Index>(rest.size()));
  for (size_t t = 0; t < rest.size(); ++t) {
    packed.col(t).head<4>() = Eigen::Map<const Eigen::Vector4d>(rest[t].dm_inverse.data());
    packed(4, t) = rest[t].area;
  }
  return packed;
}

void unpack_membrane_rest(const Eigen::MatrixXd& packed, std::vector<MembraneRest>& rest) {
  for (size_t t = 0; t < rest.size(); ++t) {
    Eigen::Map<Eigen::Vector4d>(rest[t].dm_inverse.data()) = packed.col(t).head<4>();
    rest[t].area = packed(4, t);
  }
}

}  // namespace

uint64_t checkpoint_checksum(const std::string& payload) {
  uint64_t hash = 14695981039346656037ull;
  for (const char c : payload) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

Checkpoint capture_checkpoint(const World& world, int frame, const std::string& scene_json,
                              double initial_energy, const EnergyFlows& energy_flows) {
  Checkpoint checkpoint;
  checkpoint.energy_flows = energy_flows;
  checkpoint.scene_json = scene_json;
  checkpoint.frame = frame;
  checkpoint.time = world.time();
  checkpoint.initial_energy = initial_energy;
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    const Cloth& cloth = world.cloths()[c];
    checkpoint.cloths.push_back({cloth.model.name, cloth.state.x, cloth.state.v, cloth.model.rest_positions,
                                 world.adaptive_state(static_cast<int>(c)),
                                 pack_membrane_rest(cloth.model.membrane.rest)});
  }
  for (const Collider& collider : world.colliders()) {
    checkpoint.colliders.push_back(
        {collider.name, collider.center, collider.normal, collider.radius, collider.half_extents});
  }
  checkpoint.contact_pairs = world.contact_history();
  return checkpoint;
}

void restore_checkpoint(const Checkpoint& checkpoint, World& world, const std::string& file) {
  if (checkpoint.cloths.size() != world.cloths().size() ||
      checkpoint.colliders.size() != world.colliders().size()) {
    throw IoError(file + ": checkpoint holds " + std::to_string(checkpoint.cloths.size()) + " cloths and " +
                  std::to_string(checkpoint.colliders.size()) + " colliders, the scene " +
                  std::to_string(world.cloths().size()) + " and " + std::to_string(world.colliders().size()));
  }
  for (size_t c = 0; c < checkpoint.cloths.size(); ++c) {
    const ClothCheckpoint& saved = checkpoint.cloths[c];
    Cloth& cloth = world.cloths()[c];
    if (saved.name != cloth.model.name || saved.x.cols() != cloth.num_vertices() ||
        saved.v.cols() != saved.x.cols() || saved.rest_positions.cols() != saved.x.cols() ||
        saved.membrane_rest.cols() != static_cast<Eigen::Index>(cloth.model.membrane.rest.size())) {
      throw IoError(file + ": checkpoint cloth " + std::to_string(c) + " (\"" + saved.name + "\", " +
                    std::to_string(saved.x.cols()) + " vertices, " +
                    std::to_string(saved.membrane_rest.cols()) +
                    " membrane triangles) does not match the scene's (\"" + cloth.model.name + "\", " +
                    std::to_string(cloth.num_vertices()) + " vertices, " +
                    std::to_string(cloth.model.membrane.rest.size()) + " membrane triangles)");
    }
    cloth.state.x = saved.x;
    cloth.state.v = saved.v;
    cloth.model.rest_positions = saved.rest_positions;
    unpack_membrane_rest(saved.membrane_rest, cloth.model.membrane.rest);
    world.adaptive_state(static_cast<int>(c)) = saved.adaptive;
  }
  for (size_t k = 0; k < checkpoint.colliders.size(); ++k) {
    const ColliderCheckpoint& saved = checkpoint.colliders[k];
    Collider& collider = world.colliders()[k];
    if (saved.name != collider.name) {
      throw IoError(file + ": checkpoint collider " + std::to_string(k) + " is \"" + saved.name +
                    "\", the scene's \"" + collider.name + "\"");
    }
    collider.center = saved.center;
    collider.normal = saved.normal;
    collider.radius = saved.radius;
    collider.half_extents = saved.half_extents;
  }
  world.restore_contact_history(checkpoint.contact_pairs);
  world.set_time(checkpoint.time);
}

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
  PayloadWriter payload;
  payload.string(checkpoint.scene_json);
  payload.value<int32_t>(checkpoint.frame);
  payload.value<double>(checkpoint.time);
  payload.value<double>(checkpoint.initial_energy);
  payload.value<uint32_t>(checkpoint.cloths.size());
  for (const ClothCheckpoint& cloth : checkpoint.cloths) {
    payload.string(cloth.name);
    payload.matrix(cloth.x);
    payload.matrix(cloth.v);
    payload.matrix(cloth.rest_positions);
    payload.value<double>(cloth.adaptive.next_step);
    payload.value<int32_t>(cloth.adaptive.accepted);
    payload.value<int32_t>(cloth.adaptive.rejected);
    payload.value<double>(cloth.adaptive.last_error);
    payload.matrix(cloth.membrane_rest);
  }
  payload.value<uint32_t>(checkpoint.colliders.size());
  for (const ColliderCheckpoint& collider : checkpoint.colliders) {
    payload.string(collider.name);
    payload.vec3(collider.center);
    payload.vec3(collider.normal);
    payload.value<double>(collider.radius);
    payload.vec3(collider.half_extents);
  }
  payload.value<uint64_t>(checkpoint.contact_pairs.size());
  for (const auto& pair : checkpoint.contact_pairs) {
    for (const int index : pair) payload.value<int32_t>(index);
  }
  const EnergyFlows& flows = checkpoint.energy_flows;
  for (const double flow :
       {flows.external_work, flows.damping, flows.integrator, flows.contact, flows.plastic, flows.residual}) {
    payload.value<double>(flow);
  }
  write_file_atomically(path, [&](std::ostream& out) {
    const uint32_t version = checkpoint_version, reserved = 0;
    const uint64_t size = payload.bytes().size(), hash = checkpoint_checksum(payload.bytes());
    out.write(magic, sizeof magic);
    out.write(reinterpret_cast<const char*>(&version), sizeof version);
    out.write(reinterpret_cast<const char*>(&reserved), sizeof reserved);
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(payload.bytes().data(), static_cast<std::streamsize>(size));
    out.write(reinterpret_cast<const char*>(&hash), sizeof hash);
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open checkpoint: " + std::strerror(errno));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_checkpoint(buffer.str(), path);
}

Checkpoint parse_checkpoint(const std::string& file, const std::string& path) {
  if (file.size() < header_bytes + 8 || std::memcmp(file.data(), magic, sizeof magic) != 0) {
    throw IoError(path + ": not a Weft checkpoint: expected \"WEFTCKPT\" at the start");
  }
  uint32_t version = 0;
  uint64_t size = 0, hash = 0;
  std::memcpy(&version, file.data() + 8, sizeof version);
  std::memcpy(&size, file.data() + 16, sizeof size);
  if (version != checkpoint_version && version != 4 && version != 3 && version != 2) {
    throw IoError(path + ": checkpoint version: expected " + std::to_string(checkpoint_version) + ", got " +
                  std::to_string(version));
  }
  if (size != file.size() - header_bytes - 8) {
    throw IoError(path + ": checkpoint size: the header says " + std::to_string(size) +
                  " payload bytes, the file holds " + std::to_string(file.size() - header_bytes - 8) +
                  " (cut short?)");
  }
  const std::string bytes = file.substr(header_bytes, size);
  std::memcpy(&hash, file.data() + header_bytes + size, sizeof hash);
  if (hash != checkpoint_checksum(bytes))
    throw IoError(path + ": checkpoint checksum: mismatch (the file is corrupt)");

  PayloadReader payload(bytes, path);
  Checkpoint checkpoint;
  checkpoint.scene_json = payload.string("scene");
  checkpoint.frame = payload.value<int32_t>("frame");
  checkpoint.time = payload.value<double>("time");
  checkpoint.initial_energy = payload.value<double>("initial_energy");
  const uint32_t cloths = payload.value<uint32_t>("cloth count");
  for (uint32_t c = 0; c < cloths; ++c) {
    ClothCheckpoint cloth;
    cloth.name = payload.string("cloth name");
    cloth.x = payload.positions("cloth x");
    cloth.v = payload.positions("cloth v");
    cloth.rest_positions = payload.positions("cloth rest_positions");
    cloth.adaptive.next_step = payload.value<double>("adaptive next_step");
    cloth.adaptive.accepted = payload.value<int32_t>("adaptive accepted");
    cloth.adaptive.rejected = payload.value<int32_t>("adaptive rejected");
    cloth.adaptive.last_error = payload.value<double>("adaptive last_error");
    cloth.membrane_rest = payload.matrix(5, "cloth membrane rest");
    checkpoint.cloths.push_back(std::move(cloth));
  }
  const uint32_t colliders = payload.value<uint32_t>("collider count");
  for (uint32_t k = 0; k < colliders; ++k) {
    ColliderCheckpoint collider;
    collider.name = payload.string("collider name");
    collider.center = payload.vec3("collider center");
    collider.normal = payload.vec3("collider normal");
    collider.radius = payload.value<double>("collider radius");
    collider.half_extents = payload.vec3("collider half_extents");
    checkpoint.colliders.push_back(std::move(collider));
  }
  if (version >= 3) {
    const uint64_t pairs = payload.value<uint64_t>("contact pair count");
    if (pairs > bytes.size() / 12)
      throw IoError(path + ": checkpoint field contact pair count: malformed or cut short");
    checkpoint.contact_pairs.resize(pairs);
    for (auto& pair : checkpoint.contact_pairs) {
      for (int& index : pair) index = payload.value<int32_t>("contact pair");
    }
  }
  if (version >= 4) {
    EnergyFlows& flows = checkpoint.energy_flows;
    for (double* flow :
         {&flows.external_work, &flows.damping, &flows.integrator, &flows.contact, &flows.plastic}) {
      *flow = payload.value<double>("energy flows");
    }
    if (version >= 5) flows.residual = payload.value<double>("energy flows");
  }
  if (!payload.at_end()) throw IoError(path + ": checkpoint: unexpected bytes after the energy flows");
  return checkpoint;
}

}  // namespace weft
