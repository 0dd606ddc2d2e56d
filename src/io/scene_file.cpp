#include "io/scene_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "sim/world.hpp"

namespace weft {

using nlohmann::json;

const std::vector<std::string> display_switch_names = {
    "boxes",     "no-boxes",   "contacts", "no-contacts", "wireframe", "no-wireframe", "strain",
    "no-strain", "pins",       "no-pins",  "grid",        "no-grid",   "colliders",    "no-colliders",
    "cutaway",   "no-cutaway", "panels",   "no-panels",   "tangles",   "no-tangles"};

namespace {

// Bounds on a number; `text` says them in words for the error message ("> 0").
struct Range {
  double min = -HUGE_VAL;
  double max = HUGE_VAL;
  bool min_open = false;
  std::string text;
};
const Range any_number{-HUGE_VAL, HUGE_VAL, false, ""};
const Range positive{0.0, HUGE_VAL, true, " > 0"};
const Range non_negative{0.0, HUGE_VAL, false, " >= 0"};
const Range poisson{0.0, 0.4999, false, " in [0, 0.5)"};
const Range unit_open_closed{0.0, 1.0, true, " in (0, 1]"};
const Range unit_closed{0.0, 1.0, false, " in [0, 1]"};
const Range stretch_floor{0.0, 0.99, false, " in [0, 0.99]"};

std::string type_name(const json& value) {
  if (value.is_number_integer() || value.is_number_unsigned()) return "integer " + value.dump();
  if (value.is_number_float()) return "number " + value.dump();
  if (value.is_string()) return "string " + value.dump();
  if (value.is_boolean()) return value.dump();
  if (value.is_null()) return "null";
  if (value.is_array()) return "an array";
  return "an object";
}

// Reads the members of one JSON object, checking each, and rejects members nobody asked for.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path, const std::string& file)
      : object_(object), path_(std::move(path)), file_(file) {
    if (!object_.is_object()) fail(path_, "expected an object, got " + type_name(object_));
  }

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw SceneError(file_, path, message);
  }
  std::string path_of(const std::string& key) const { return path_ + "/" + key; }
  bool has(const std::string& key) const { return object_.contains(key); }

  // Marks `key` as known and returns its value, or null when absent.
  const json* find(const std::string& key) {
    known_.insert(key);
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  void number(const std::string& key, double& out, const Range& range = any_number) {
    if (const json* value = find(key)) out = to_number(*value, path_of(key), range);
  }

  void integer(const std::string& key, int& out, int min, int max) {
    if (const json* value = find(key)) out = to_integer(*value, path_of(key), min, max);
  }

  void string(const std::string& key, std::string& out) {
    if (const json* value = find(key)) {
      if (!value->is_string()) fail(path_of(key), "expected a string, got " + type_name(*value));
      out = value->get<std::string>();
    }
  }

  void vec3(const std::string& key, Vec3& out) {
    if (const json* value = find(key)) {
      const std::string path = path_of(key);
      if (!value->is_array() || value->size() != 3) {
        fail(path, "expected an array of 3 numbers, got " + type_name(*value) +
                       (value->is_array() ? " of " + std::to_string(value->size()) : ""));
      }
      for (int k = 0; k < 3; ++k) out[k] = to_number((*value)[k], path + "/" + std::to_string(k), any_number);
    }
  }

  // A pair of numbers, e.g. a grid's size.
  void pair(const std::string& key, double& first, double& second, const Range& range) {
    if (const json* value = find(key)) {
      const std::string path = path_of(key);
      if (!value->is_array() || value->size() != 2) fail(path, "expected an array of 2 numbers");
      first = to_number((*value)[0], path + "/0", range);
      second = to_number((*value)[1], path + "/1", range);
    }
  }

  void integer_pair(const std::string& key, int& first, int& second, int min, int max) {
    if (const json* value = find(key)) {
      const std::string path = path_of(key);
      if (!value->is_array() || value->size() != 2) fail(path, "expected an array of 2 integers");
      first = to_integer((*value)[0], path + "/0", min, max);
      second = to_integer((*value)[1], path + "/1", min, max);
    }
  }

  void boolean(const std::string& key, bool& out) {
    if (const json* value = find(key)) {
      if (!value->is_boolean()) fail(path_of(key), "expected true or false, got " + type_name(*value));
      out = value->get<bool>();
    }
  }

  template <typename Enum>
  void enumeration(const std::string& key, Enum& out,
                   const std::vector<std::pair<std::string, Enum>>& names) {
    if (const json* value = find(key)) {
      std::string expected;
      for (const auto& [name, item] : names) expected += (expected.empty() ? "\"" : ", \"") + name + "\"";
      if (value->is_string()) {
        for (const auto& [name, item] : names) {
          if (name == value->get<std::string>()) {
            out = item;
            return;
          }
        }
      }
      fail(path_of(key), "expected one of " + expected + ", got " + type_name(*value));
    }
  }

  // Rejects every member that no reader asked for.
  void finish() const {
    for (const auto& [key, value] : object_.items()) {
      if (known_.count(key) == 0) {
        std::string known_list;
        for (const std::string& name : known_) known_list += (known_list.empty() ? "" : ", ") + name;
        fail(path_of(key), "unknown key \"" + key + "\" (known here: " + known_list + ")");
      }
    }
  }

  double to_number(const json& value, const std::string& path, const Range& range) const {
    if (!value.is_number()) fail(path, "expected a number" + range.text + ", got " + type_name(value));
    const double number = value.get<double>();
    if (!std::isfinite(number)) fail(path, "expected a finite number" + range.text + ", got " + value.dump());
    const bool below = range.min_open ? number <= range.min : number < range.min;
    if (below || number > range.max) fail(path, "expected a number" + range.text + ", got " + value.dump());
    return number;
  }

  int to_integer(const json& value, const std::string& path, int min, int max) const {
    const std::string expected =
        "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    if (!value.is_number_integer() && !value.is_number_unsigned())
      fail(path, expected + ", got " + type_name(value));
    const long long number = value.get<long long>();
    if (number < min || number > max) fail(path, expected + ", got " + value.dump());
    return static_cast<int>(number);
  }

 private:
  const json& object_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> known_;
};

const std::vector<std::pair<std::string, GridTriangulation>> triangulation_names = {
    {"regular", GridTriangulation::regular},
    {"alternating", GridTriangulation::alternating},
    {"cross", GridTriangulation::cross}};
const std::vector<std::pair<std::string, ColliderShape>> collider_shape_names = {
    {"plane", ColliderShape::plane},       {"sphere", ColliderShape::sphere},
    {"box", ColliderShape::box},           {"capsule", ColliderShape::capsule},
    {"cylinder", ColliderShape::cylinder}, {"mesh", ColliderShape::mesh}};
const std::vector<std::pair<std::string, CollisionResponse>> response_names = {
    {"impulse", CollisionResponse::impulse}, {"barrier", CollisionResponse::barrier}};

const std::vector<std::pair<std::string, IntegratorKind>> integrator_names = {
    {"symplectic_euler", IntegratorKind::symplectic_euler},
    {"midpoint_euler_cromer", IntegratorKind::midpoint_euler_cromer},
    {"explicit_midpoint", IntegratorKind::explicit_midpoint},
    {"implicit_euler", IntegratorKind::implicit_euler},
    {"xpbd", IntegratorKind::xpbd}};
const std::vector<std::pair<std::string, LinearSolverKind>> linear_solver_names = {
    {"conjugate_gradient", LinearSolverKind::conjugate_gradient}, {"cholesky", LinearSolverKind::cholesky}};
const std::vector<std::pair<std::string, Preconditioner>> preconditioner_names = {
    {"gauss_seidel", Preconditioner::symmetric_gauss_seidel}, {"block_jacobi", Preconditioner::block_jacobi}};
const std::vector<std::pair<std::string, BendingModel>> bending_model_names = {
    {"dihedral", BendingModel::dihedral}, {"quadratic", BendingModel::quadratic}};
const Range pitch_range{-88.0, 88.0, false, " in [-88, 88]"};
const std::vector<std::string> corner_names = {"bottom_left", "bottom_right", "top_left", "top_right"};
const std::vector<std::string> edge_names = {"bottom", "top", "left", "right"};

template <typename Enum>
std::string name_of(Enum item, const std::vector<std::pair<std::string, Enum>>& names) {
  for (const auto& [name, candidate] : names) {
    if (candidate == item) return name;
  }
  return "unknown";
}

constexpr int max_grid_resolution = 4096;

void read_spring(ObjectReader& springs, const std::string& kind, SpringParams& params,
                 const std::string& file) {
  if (const json* value = springs.find(kind)) {
    ObjectReader spring(*value, springs.path_of(kind), file);
    spring.number("stiffness", params.stiffness, non_negative);
    spring.number("damping", params.damping, non_negative);
    spring.finish();
  }
}

// A list of names, each from `allowed`.
void read_names(ObjectReader& reader, const std::string& key, std::vector<std::string>& out,
                const std::vector<std::string>& allowed) {
  if (const json* value = reader.find(key)) {
    const std::string path = reader.path_of(key);
    if (!value->is_array()) reader.fail(path, "expected an array of strings, got " + type_name(*value));
    std::string expected;
    for (const std::string& name : allowed) expected += (expected.empty() ? "\"" : ", \"") + name + "\"";
    out.clear();
    for (size_t k = 0; k < value->size(); ++k) {
      const json& item = (*value)[k];
      if (!item.is_string() ||
          std::find(allowed.begin(), allowed.end(), item.get<std::string>()) == allowed.end()) {
        reader.fail(path + "/" + std::to_string(k),
                    "expected one of " + expected + ", got " + type_name(item));
      }
      out.push_back(item.get<std::string>());
    }
  }
}

// A pin selection: "vertices", "corners" and "edges" read from `reader`'s object.
PinSelection read_pin_selection(ObjectReader& reader) {
  PinSelection selection;
  if (const json* vertices = reader.find("vertices")) {
    const std::string vertices_path = reader.path_of("vertices");
    if (!vertices->is_array()) reader.fail(vertices_path, "expected an array of vertex indices");
    for (size_t k = 0; k < vertices->size(); ++k) {
      selection.vertices.push_back(
          reader.to_integer((*vertices)[k], vertices_path + "/" + std::to_string(k), 0, 1 << 30));
    }
  }
  read_names(reader, "corners", selection.corners, corner_names);
  read_names(reader, "edges", selection.edges, edge_names);
  return selection;
}

// Named corners and edges need a grid.
void require_grid_for_names(const ObjectReader& reader, const ClothDesc& cloth,
                            const PinSelection& selection) {
  const bool grid = cloth.obj_file.empty() && !cloth.sphere;
  if (!grid && (!selection.corners.empty() || !selection.edges.empty())) {
    reader.fail(reader.path_of(selection.corners.empty() ? "edges" : "corners"),
                "named corners and edges exist only on grid cloths; pin other meshes by \"vertices\"");
  }
}

ClothDesc read_cloth(const json& value, const std::string& path, const std::string& file) {
  ClothDesc cloth;
  ObjectReader reader(value, path, file);
  reader.string("name", cloth.name);
  if (static_cast<int>(reader.has("grid")) + reader.has("obj") + reader.has("sphere") > 1) {
    reader.fail(path, "a cloth takes one of \"grid\", \"obj\" or \"sphere\", not several");
  }
  if (const json* grid_value = reader.find("grid")) {
    ObjectReader grid(*grid_value, reader.path_of("grid"), file);
    grid.pair("size", cloth.grid_width, cloth.grid_height, positive);
    grid.integer_pair("resolution", cloth.grid_nx, cloth.grid_ny, 2, max_grid_resolution);
    grid.enumeration("triangulation", cloth.triangulation, triangulation_names);
    grid.finish();
  }
  reader.string("obj", cloth.obj_file);
  if (reader.has("obj") && cloth.obj_file.empty()) reader.fail(reader.path_of("obj"), "expected a file name");
  if (const json* sphere_value = reader.find("sphere")) {
    ObjectReader sphere(*sphere_value, reader.path_of("sphere"), file);
    cloth.sphere = true;
    sphere.number("radius", cloth.sphere_radius, positive);
    sphere.integer("slices", cloth.sphere_slices, 3, 1024);
    sphere.integer("stacks", cloth.sphere_stacks, 2, 1024);
    sphere.finish();
  }
  if (const json* transform_value = reader.find("transform")) {
    ObjectReader transform(*transform_value, reader.path_of("transform"), file);
    transform.vec3("translation", cloth.translation);
    transform.vec3("rotation_degrees", cloth.rotation_degrees);
    transform.number("scale", cloth.scale, positive);
    transform.finish();
  }
  reader.number("density", cloth.density, positive);
  reader.number("mass", cloth.mass, non_negative);
  const json* springs_value = reader.find("springs");
  if (springs_value == nullptr && reader.find("membrane") != nullptr) {
    // A continuum membrane replaces the lattice springs unless the scene asks for both.
    cloth.structural = cloth.shear = cloth.bend = SpringParams{0.0, 0.0};
  }
  if (springs_value != nullptr) {
    ObjectReader springs(*springs_value, reader.path_of("springs"), file);
    read_spring(springs, "structural", cloth.structural, file);
    read_spring(springs, "shear", cloth.shear, file);
    read_spring(springs, "bend", cloth.bend, file);
    springs.finish();
  }
  if (const json* membrane_value = reader.find("membrane")) {
    ObjectReader membrane(*membrane_value, reader.path_of("membrane"), file);
    cloth.membrane = true;
    MembraneMaterial& material = cloth.membrane_material;
    membrane.number("young_modulus", material.young_modulus, positive);
    membrane.number("poisson_ratio", material.poisson_ratio, poisson);
    membrane.number("thickness", material.thickness, positive);
    membrane.number("compression_factor", material.compression_factor, unit_open_closed);
    membrane.number("min_stretch", material.min_stretch, stretch_floor);
    membrane.number("yield_strain", cloth.yield_strain, non_negative);
    membrane.number("plastic_flow", cloth.plastic_flow, unit_closed);
    membrane.finish();
  }
  if (const json* bending_value = reader.find("bending")) {
    ObjectReader bending(*bending_value, reader.path_of("bending"), file);
    cloth.bending = true;
    bending.number("stiffness", cloth.bending_stiffness, non_negative);
    bending.enumeration("model", cloth.bending_model, bending_model_names);
    bending.finish();
  }
  if (const json* drag_value = reader.find("air_drag")) {
    ObjectReader drag(*drag_value, reader.path_of("air_drag"), file);
    drag.number("normal", cloth.normal_drag, non_negative);
    drag.number("tangential", cloth.tangential_drag, non_negative);
    drag.finish();
  }
  if (const json* pressure_value = reader.find("pressure")) {
    ObjectReader pressure(*pressure_value, reader.path_of("pressure"), file);
    cloth.pressure = true;
    pressure.number("bulk_modulus", cloth.bulk_modulus, positive);
    pressure.number("pressure_scale", cloth.pressure_scale, positive);
    pressure.finish();
  }
  reader.number("thickness", cloth.thickness, positive);
  reader.number("mass_damping", cloth.mass_damping, non_negative);
  if (const json* friction_value = reader.find("friction")) {
    ObjectReader friction(*friction_value, reader.path_of("friction"), file);
    friction.number("static", cloth.contact.static_friction, non_negative);
    friction.number("kinetic", cloth.contact.kinetic_friction, non_negative);
    friction.finish();
  }
  reader.boolean("self_collision", cloth.contact.self_collision);
  reader.vec3("initial_velocity", cloth.initial_velocity);
  if (const json* pins_value = reader.find("pins")) {
    ObjectReader pins(*pins_value, reader.path_of("pins"), file);
    cloth.pins = read_pin_selection(pins);
    pins.finish();
    require_grid_for_names(pins, cloth, cloth.pins);
  }
  if (const json* moving = reader.find("moving_pins")) {
    const std::string moving_path = reader.path_of("moving_pins");
    if (!moving->is_array())
      reader.fail(moving_path, "expected an array of moving pin groups, got " + type_name(*moving));
    for (size_t k = 0; k < moving->size(); ++k) {
      ObjectReader group((*moving)[k], moving_path + "/" + std::to_string(k), file);
      MovingPinDesc desc;
      desc.selection = read_pin_selection(group);
      group.vec3("velocity", desc.velocity);
      group.vec3("center", desc.center);
      group.vec3("axis", desc.axis);
      group.number("angular_velocity_degrees", desc.angular_velocity_degrees);
      group.finish();
      if (!(desc.axis.norm() > 1e-12)) group.fail(group.path_of("axis"), "expected a non-zero vector");
      desc.axis.normalize();
      if (desc.selection.empty())
        group.fail(group.path_of("vertices"), "expected at least one vertex, corner or edge");
      require_grid_for_names(group, cloth, desc.selection);
      cloth.moving_pins.push_back(std::move(desc));
    }
  }
  reader.finish();
  return cloth;
}

// A unit vector; `what` names it in the error.
void read_direction(ObjectReader& reader, const std::string& key, Vec3& out) {
  reader.vec3(key, out);
  const double length = out.norm();
  if (!(length > 1e-12)) reader.fail(reader.path_of(key), "expected a non-zero vector");
  out /= length;
}

Collider read_collider(const json& value, const std::string& path, const std::string& file) {
  Collider collider;
  ObjectReader reader(value, path, file);
  if (!reader.has("type")) {
    reader.fail(path,
                "missing \"type\": expected one of \"plane\", \"sphere\", \"box\", \"capsule\", "
                "\"cylinder\", \"mesh\"");
  }
  reader.enumeration("type", collider.shape, collider_shape_names);
  reader.string("name", collider.name);
  if (collider.name.empty()) collider.name = to_string(collider.shape);
  // "friction" is the kinetic coefficient and, unless "static_friction" says otherwise, the static one.
  reader.number("friction", collider.friction, non_negative);
  collider.static_friction = collider.friction;
  reader.number("static_friction", collider.static_friction, non_negative);
  switch (collider.shape) {
    case ColliderShape::plane:
      reader.vec3("point", collider.center);
      read_direction(reader, "normal", collider.normal);
      reader.number("half_size", collider.plane_half_size, positive);
      break;
    case ColliderShape::sphere:
      reader.vec3("center", collider.center);
      reader.number("radius", collider.radius, positive);
      break;
    case ColliderShape::box:
      reader.vec3("center", collider.center);
      reader.vec3("half_extents", collider.half_extents);
      for (int k = 0; k < 3; ++k) {
        if (!(collider.half_extents[k] > 0.0)) {
          reader.fail(reader.path_of("half_extents") + "/" + std::to_string(k), "expected a number > 0");
        }
      }
      break;
    case ColliderShape::capsule:
    case ColliderShape::cylinder:
      reader.vec3("center", collider.center);
      read_direction(reader, "axis", collider.axis);
      reader.number("radius", collider.radius, positive);
      reader.number("half_length", collider.half_length, positive);
      if (collider.shape == ColliderShape::cylinder) reader.boolean("capped", collider.capped);
      break;
    case ColliderShape::mesh:
      if (!reader.has("obj")) reader.fail(path, "missing \"obj\": a mesh collider needs an OBJ file");
      reader.string("obj", collider.obj_file);
      if (collider.obj_file.empty()) reader.fail(reader.path_of("obj"), "expected a file name");
      break;
  }
  if (const json* motion_value = reader.find("motion")) {
    ObjectReader motion(*motion_value, reader.path_of("motion"), file);
    motion.vec3("velocity", collider.motion.velocity);
    motion.vec3("pivot", collider.motion.pivot);
    if (motion.has("axis")) read_direction(motion, "axis", collider.motion.axis);
    double degrees = 0.0;
    motion.number("angular_velocity_degrees", degrees);
    collider.motion.angular_velocity = degrees * pi / 180.0;
    motion.finish();
  }
  reader.finish();
  return collider;
}

// Implicit Euler's tolerance must lie below resting_start_residual() (implicit_euler.hpp), or a
// step may end off by gravity's whole pull over it and report convergence. Checked for the
// scene's own step (an adaptive run's smaller steps are not).
void check_newton_tolerance(const ObjectReader& reader, const SceneDesc& scene) {
  if (scene.integrator != IntegratorKind::implicit_euler) return;
  const double h = scene.time_step / scene.substeps;
  const double gravity_velocity = resting_start_residual(scene.gravity, h);
  if (!(scene.implicit.newton_tolerance >= gravity_velocity) || gravity_velocity == 0.0) return;
  std::ostringstream message;
  message << std::setprecision(4) << "expected a tolerance below " << gravity_velocity
          << " m/s, the velocity gravity adds in one step of " << h
          << " s (at or above it a step may end off "
          << "by gravity's whole pull and report convergence), got " << scene.implicit.newton_tolerance;
  reader.fail("/solver/newton/tolerance", message.str());
}

// A frame must fit in max_steps_per_frame integration sub-steps: a run asking for more could not
// finish (1e-12 s steps are 3e10 a frame), so it is refused before anything is built.
void check_steps_per_frame(const ObjectReader& reader, const SceneDesc& scene) {
  const double steps = steps_per_frame(scene.fps, scene.time_step);
  const double solver_sub_steps = steps * scene.substeps;
  const double xpbd_substeps = scene.integrator == IntegratorKind::xpbd ? scene.xpbd.substeps : 1;
  if (solver_sub_steps * xpbd_substeps <= max_steps_per_frame) return;
  std::ostringstream message;
  message << std::setprecision(4);
  const auto too_many = [&](double count) {
    message << ": " << count << " sub-steps per frame, more than the " << max_steps_per_frame
            << " a run can finish in";
  };
  if (steps > max_steps_per_frame) {
    message << "expected a time step of at least " << 1.0 / scene.fps / max_steps_per_frame << " s at "
            << scene.fps << " fps, got " << scene.time_step;
    too_many(steps);
    reader.fail("/solver/time_step", message.str());
  }
  if (solver_sub_steps > max_steps_per_frame) {
    message << "expected at most " << static_cast<long long>(max_steps_per_frame / steps) << " substeps with "
            << steps << " steps per frame, got " << scene.substeps;
    too_many(solver_sub_steps);
    reader.fail("/solver/substeps", message.str());
  }
  message << "expected at most " << static_cast<long long>(max_steps_per_frame / solver_sub_steps)
          << " XPBD substeps with " << solver_sub_steps << " steps per frame, got " << scene.xpbd.substeps;
  too_many(solver_sub_steps * xpbd_substeps);
  reader.fail("/solver/xpbd/substeps", message.str());
}

json to_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

// Splits "a.b.0.c" or "/a/b/0/c" into tokens.
std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> tokens;
  const char separator = !path.empty() && path[0] == '/' ? '/' : '.';
  std::string token;
  std::istringstream stream(separator == '/' ? path.substr(1) : path);
  while (std::getline(stream, token, separator)) tokens.push_back(token);
  return tokens;
}

// Contact inside the solve (sim/barrier_contact.hpp) runs in implicit Euler's Newton solve and
// holds colliders still during it: other integrators and moving colliders are refused, not
// silently given the impulse response.
void check_barrier_response(const ObjectReader& reader, const SceneDesc& scene) {
  if (scene.collision.response != CollisionResponse::barrier || !scene.collision.enabled) return;
  if (scene.integrator != IntegratorKind::implicit_euler) {
    reader.fail("/collision/response", "the \"barrier\" response needs solver.integrator \"implicit_euler\"");
  }
  for (size_t k = 0; k < scene.colliders.size(); ++k) {
    if (!scene.colliders[k].motion.is_static()) {
      reader.fail("/collision/response", "the \"barrier\" response needs static colliders; collider " +
                                             std::to_string(k) + " (\"" + scene.colliders[k].name +
                                             "\") moves: use \"impulse\"");
    }
  }
}

}  // namespace

SceneDesc parse_scene(const json& document, const std::string& file) {
  SceneDesc scene;
  scene.source_file = file;
  ObjectReader reader(document, "", file);
  reader.string("name", scene.name);
  reader.vec3("gravity", scene.gravity);
  reader.vec3("wind", scene.wind);
  if (const json* solver_value = reader.find("solver")) {
    ObjectReader solver(*solver_value, "/solver", file);
    solver.enumeration("integrator", scene.integrator, integrator_names);
    solver.number("time_step", scene.time_step, positive);
    solver.integer("substeps", scene.substeps, 1, 100000);
    solver.number("max_travel_edges", scene.max_travel_edges, non_negative);
    if (const json* newton_value = solver.find("newton")) {
      ObjectReader newton(*newton_value, "/solver/newton", file);
      newton.number("tolerance", scene.implicit.newton_tolerance, positive);
      newton.integer("max_iterations", scene.implicit.max_newton_iterations, 1, 10000);
      newton.enumeration("linear_solver", scene.implicit.linear_solver, linear_solver_names);
      newton.number("cg_tolerance", scene.implicit.cg_tolerance, positive);
      newton.number("cg_initial_tolerance", scene.implicit.cg_initial_tolerance, positive);
      newton.integer("max_cg_iterations", scene.implicit.max_cg_iterations, 1, 1000000);
      newton.enumeration("cg_preconditioner", scene.implicit.cg_preconditioner, preconditioner_names);
      newton.finish();
    }
    if (const json* xpbd_value = solver.find("xpbd")) {
      ObjectReader xpbd(*xpbd_value, "/solver/xpbd", file);
      xpbd.integer("substeps", scene.xpbd.substeps, 1, 100000);
      xpbd.integer("iterations", scene.xpbd.iterations, 1, 100000);
      xpbd.finish();
    }
    if (const json* adaptive_value = solver.find("adaptive")) {
      ObjectReader adaptive(*adaptive_value, "/solver/adaptive", file);
      adaptive.boolean("enabled", scene.adaptive.enabled);
      adaptive.number("tolerance", scene.adaptive.tolerance, positive);
      adaptive.number("min_step", scene.adaptive.h_min, positive);
      adaptive.number("max_step", scene.adaptive.h_max, positive);
      if (scene.adaptive.h_min > scene.adaptive.h_max) {
        adaptive.fail("/solver/adaptive/min_step", "expected min_step <= max_step");
      }
      adaptive.finish();
    }
    solver.finish();
  }
  reader.number("fps", scene.fps, Range{min_fps, max_fps, false, " in [1, 10000]"});
  reader.integer("frames", scene.frames, 0, max_frames);
  check_steps_per_frame(reader, scene);
  check_newton_tolerance(reader, scene);
  if (const json* cloths = reader.find("cloths")) {
    if (!cloths->is_array()) reader.fail("/cloths", "expected an array of cloths, got " + type_name(*cloths));
    for (size_t k = 0; k < cloths->size(); ++k) {
      scene.cloths.push_back(read_cloth((*cloths)[k], "/cloths/" + std::to_string(k), file));
    }
  }
  if (const json* collision_value = reader.find("collision")) {
    ObjectReader collision(*collision_value, "/collision", file);
    CollisionSettings& settings = scene.collision;
    collision.boolean("enabled", settings.enabled);
    collision.enumeration("response", settings.response, response_names);
    collision.number("contact_radius", settings.barrier.contact_radius, non_negative);
    collision.number("contact_stiffness_ratio", settings.barrier.stiffness_ratio, positive);
    collision.number("slip_speed", settings.barrier.slip_speed, positive);
    collision.boolean("analytic_colliders", settings.barrier.analytic_colliders);
    collision.number("repulsion_stiffness", settings.repulsion_stiffness, non_negative);
    collision.number("ccd_tolerance", settings.ccd_tolerance, positive);
    collision.number("ccd_separation", settings.ccd_separation, unit_closed);
    collision.integer("max_ccd_passes", settings.max_ccd_passes, 1, 1000);
    collision.integer("max_impact_zone_passes", settings.max_impact_zone_passes, 1, 10000);
    collision.integer("max_rounds", settings.max_rounds, 1, 100);
    collision.number("penalty_stiffness", settings.penalty_stiffness, non_negative);
    collision.number("collider_contact_ratio", settings.collider_contact_ratio, non_negative);
    collision.number("strain_limit", settings.strain_limit, non_negative);
    collision.integer("strain_limit_sweeps", settings.strain_limit_sweeps, 1, 1000);
    collision.number("bvh_rebuild_ratio", settings.bvh.rebuild_ratio, Range{1.0, HUGE_VAL, true, " > 1"});
    collision.boolean("self_culling", settings.self_culling.enabled);
    collision.boolean("untangle", settings.untangle);
    collision.finish();
  }
  if (const json* colliders = reader.find("colliders")) {
    if (!colliders->is_array()) {
      reader.fail("/colliders", "expected an array of colliders, got " + type_name(*colliders));
    }
    for (size_t k = 0; k < colliders->size(); ++k) {
      scene.colliders.push_back(read_collider((*colliders)[k], "/colliders/" + std::to_string(k), file));
    }
  }
  check_barrier_response(reader, scene);
  if (const json* view_value = reader.find("view")) {
    ObjectReader view(*view_value, "/view", file);
    if (view.has("target")) scene.view.has_target = true;
    view.vec3("target", scene.view.target);
    view.number("distance", scene.view.distance, positive);
    view.number("yaw_degrees", scene.view.yaw_degrees);
    view.number("pitch_degrees", scene.view.pitch_degrees, pitch_range);
    read_names(view, "show", scene.view.show, display_switch_names);
    view.number("impulse_scale", scene.view.impulse_scale, positive);
    view.number("max_arrow_length", scene.view.max_arrow_length, Range{0.0, 1.0, true, " in (0, 1]"});
    view.finish();
  }
  reader.finish();
  return scene;
}

std::string apply_override(json& document, const std::string& assignment) {
  const std::string source = "--set " + assignment;
  const size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw SceneError(source, "", "expected path=value, e.g. solver.time_step=0.001");
  }
  const std::vector<std::string> tokens = split_path(assignment.substr(0, equals));
  const std::string text = assignment.substr(equals + 1);
  // The value is JSON when it parses as JSON, otherwise a plain string (--set solver.integrator=midpoint).
  json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) {
    // A bare string is written back into run.json and checkpoints, which JSON allows only as UTF-8.
    value = text;
    try {
      (void)value.dump();
    } catch (const json::type_error&) {
      throw SceneError(source, "", "the value is neither JSON nor UTF-8 text");
    }
  }

  json* node = &document;
  std::string path;
  std::string written;  // the first member the override creates, if any
  for (size_t k = 0; k < tokens.size(); ++k) {
    const std::string& token = tokens[k];
    if (token.empty()) throw SceneError(source, path, "empty path component");
    const bool last = k + 1 == tokens.size();
    if (node->is_array()) {
      // Nine digits at most: no array is that long, and std::stoul would throw past its range.
      const bool numeric = token.find_first_not_of("0123456789") == std::string::npos && token.size() <= 9;
      const size_t index = numeric ? std::stoul(token) : 0;
      if (!numeric || index >= node->size()) {
        throw SceneError(source, path + "/" + token,
                         "expected an index below " + std::to_string(node->size()) + " into this array");
      }
      node = &(*node)[index];
    } else {
      if (node->is_null()) {
        *node = json::object();
        if (written.empty()) written = path;
      }
      if (!node->is_object()) {
        throw SceneError(source, path, "cannot descend into " + type_name(*node) + " with \"" + token + "\"");
      }
      if (!node->contains(token)) {
        if (written.empty()) written = path + "/" + token;
        if (!last) (*node)[token] = json::object();
      }
      node = &(*node)[token];
    }
    path += "/" + token;
  }
  *node = std::move(value);
  return written.empty() ? path : written;
}

namespace {

// `error` as the error of the last override whose part (a JSON pointer) holds its path.
SceneError naming_override(const SceneError& error,
                           const std::vector<std::pair<std::string, std::string>>& parts) {
  const std::string& at = error.json_path();
  const std::string what = error.what();
  const std::string located = printable_text(error.file() + ": " + (at.empty() ? "/" : at) + ": ");
  if (what.compare(0, located.size(), located) != 0) return error;
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) {
    const std::string& part = it->first;
    if (at.compare(0, part.size(), part) == 0 && (at.size() == part.size() || at[part.size()] == '/')) {
      return SceneError("--set " + it->second, at, what.substr(located.size()));
    }
  }
  return error;
}

}  // namespace

SceneError naming_override(const SceneError& error, const std::vector<std::string>& overrides) {
  // After parse_scene every override's path exists in the scene, so its part is its path.
  std::vector<std::pair<std::string, std::string>> parts;
  for (const std::string& assignment : overrides) {
    const size_t equals = assignment.find('=');
    if (equals == std::string::npos) continue;
    std::string pointer;
    for (const std::string& token : split_path(assignment.substr(0, equals))) pointer += "/" + token;
    parts.emplace_back(pointer, assignment);
  }
  return naming_override(error, parts);
}

SceneDesc load_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  // A folder opens as a stream but fails on the first read (an uncaught ios_base::failure).
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw SceneError(path, "", "is a folder; expected a scene file (JSON), e.g. scenes/default.json");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int cause = errno;
    const std::string tried = std::filesystem::absolute(path, ignored).lexically_normal().string();
    throw SceneError(path, "", "cannot open the scene file " + tried + ": " + std::strerror(cause));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path, "", "cannot read the scene file");
  return parse_scene_text(text.str(), path, overrides);
}

SceneDesc parse_scene_text(const std::string& text, const std::string& file,
                           const std::vector<std::string>& overrides) {
  json document = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) {
    // Parse again with exceptions to get nlohmann's message, which has the line and column.
    try {
      document = json::parse(text);
    } catch (const json::exception& error) {
      // A parse_error, or an out_of_range for a number past a double's range (1e400).
      std::string message = error.what();
      const size_t detail = message.find("parse error"), id_end = message.find("] ");
      if (detail != std::string::npos) {
        message = message.substr(detail);
      } else if (id_end != std::string::npos) {
        message = message.substr(id_end + 2);  // without "[json.exception.out_of_range.406] "
      }
      throw SceneError(file, "", "invalid JSON: " + message);
    }
  }
  // What each override wrote (a JSON pointer), to name the override in an error inside it.
  std::vector<std::pair<std::string, std::string>> written;
  for (const std::string& assignment : overrides)
    written.emplace_back(apply_override(document, assignment), assignment);
  try {
    return parse_scene(document, file);
  } catch (const SceneError& error) {
    throw naming_override(error, written);
  }
}

json scene_to_json(const SceneDesc& scene) {
  json document;
  document["name"] = scene.name;
  document["gravity"] = to_json(scene.gravity);
  document["wind"] = to_json(scene.wind);
  document["solver"] = {
      {"integrator", name_of(scene.integrator, integrator_names)},
      {"time_step", scene.time_step},
      {"substeps", scene.substeps},
      {"max_travel_edges", scene.max_travel_edges},
      {"newton",
       {{"tolerance", scene.implicit.newton_tolerance},
        {"max_iterations", scene.implicit.max_newton_iterations},
        {"linear_solver", name_of(scene.implicit.linear_solver, linear_solver_names)},
        {"cg_tolerance", scene.implicit.cg_tolerance},
        {"cg_initial_tolerance", scene.implicit.cg_initial_tolerance},
        {"max_cg_iterations", scene.implicit.max_cg_iterations},
        {"cg_preconditioner", name_of(scene.implicit.cg_preconditioner, preconditioner_names)}}},
      {"xpbd", {{"substeps", scene.xpbd.substeps}, {"iterations", scene.xpbd.iterations}}},
      {"adaptive",
       {{"enabled", scene.adaptive.enabled},
        {"tolerance", scene.adaptive.tolerance},
        {"min_step", scene.adaptive.h_min},
        {"max_step", scene.adaptive.h_max}}}};
  document["fps"] = scene.fps;
  document["frames"] = scene.frames;
  document["cloths"] = json::array();
  for (const ClothDesc& cloth : scene.cloths) {
    json item;
    item["name"] = cloth.name;
    if (cloth.sphere) {
      item["sphere"] = {
          {"radius", cloth.sphere_radius}, {"slices", cloth.sphere_slices}, {"stacks", cloth.sphere_stacks}};
    } else if (cloth.obj_file.empty()) {
      item["grid"] = {{"size", {cloth.grid_width, cloth.grid_height}},
                      {"resolution", {cloth.grid_nx, cloth.grid_ny}},
                      {"triangulation", name_of(cloth.triangulation, triangulation_names)}};
    } else {
      item["obj"] = cloth.obj_file;
    }
    item["transform"] = {{"translation", to_json(cloth.translation)},
                         {"rotation_degrees", to_json(cloth.rotation_degrees)},
                         {"scale", cloth.scale}};
    item["density"] = cloth.density;
    item["mass"] = cloth.mass;
    const auto spring = [](const SpringParams& p) {
      return json{{"stiffness", p.stiffness}, {"damping", p.damping}};
    };
    item["springs"] = {{"structural", spring(cloth.structural)},
                       {"shear", spring(cloth.shear)},
                       {"bend", spring(cloth.bend)}};
    if (cloth.membrane) {
      const MembraneMaterial& material = cloth.membrane_material;
      item["membrane"] = {
          {"young_modulus", material.young_modulus}, {"poisson_ratio", material.poisson_ratio},
          {"thickness", material.thickness},         {"compression_factor", material.compression_factor},
          {"min_stretch", material.min_stretch},     {"yield_strain", cloth.yield_strain},
          {"plastic_flow", cloth.plastic_flow}};
    }
    if (cloth.bending) {
      item["bending"] = {{"stiffness", cloth.bending_stiffness},
                         {"model", name_of(cloth.bending_model, bending_model_names)}};
    }
    item["air_drag"] = {{"normal", cloth.normal_drag}, {"tangential", cloth.tangential_drag}};
    if (cloth.pressure) {
      item["pressure"] = {{"bulk_modulus", cloth.bulk_modulus}, {"pressure_scale", cloth.pressure_scale}};
    }
    item["thickness"] = cloth.thickness;
    item["mass_damping"] = cloth.mass_damping;
    item["friction"] = {{"static", cloth.contact.static_friction},
                        {"kinetic", cloth.contact.kinetic_friction}};
    item["self_collision"] = cloth.contact.self_collision;
    item["initial_velocity"] = to_json(cloth.initial_velocity);
    const auto selection = [](const PinSelection& s) {
      return json{{"vertices", s.vertices}, {"corners", s.corners}, {"edges", s.edges}};
    };
    item["pins"] = selection(cloth.pins);
    item["moving_pins"] = json::array();
    for (const MovingPinDesc& moving : cloth.moving_pins) {
      json group = selection(moving.selection);
      group["velocity"] = to_json(moving.velocity);
      group["center"] = to_json(moving.center);
      group["axis"] = to_json(moving.axis);
      group["angular_velocity_degrees"] = moving.angular_velocity_degrees;
      item["moving_pins"].push_back(group);
    }
    document["cloths"].push_back(item);
  }
  document["collision"] = {{"enabled", scene.collision.enabled},
                           {"repulsion_stiffness", scene.collision.repulsion_stiffness},
                           {"ccd_tolerance", scene.collision.ccd_tolerance},
                           {"ccd_separation", scene.collision.ccd_separation},
                           {"max_ccd_passes", scene.collision.max_ccd_passes},
                           {"max_impact_zone_passes", scene.collision.max_impact_zone_passes},
                           {"max_rounds", scene.collision.max_rounds},
                           {"response", name_of(scene.collision.response, response_names)},
                           {"contact_radius", scene.collision.barrier.contact_radius},
                           {"contact_stiffness_ratio", scene.collision.barrier.stiffness_ratio},
                           {"slip_speed", scene.collision.barrier.slip_speed},
                           {"analytic_colliders", scene.collision.barrier.analytic_colliders},
                           {"penalty_stiffness", scene.collision.penalty_stiffness},
                           {"collider_contact_ratio", scene.collision.collider_contact_ratio},
                           {"strain_limit", scene.collision.strain_limit},
                           {"strain_limit_sweeps", scene.collision.strain_limit_sweeps},
                           {"bvh_rebuild_ratio", scene.collision.bvh.rebuild_ratio},
                           {"self_culling", scene.collision.self_culling.enabled},
                           {"untangle", scene.collision.untangle}};
  document["colliders"] = json::array();
  for (const Collider& collider : scene.colliders) {
    json item = {{"type", to_string(collider.shape)},
                 {"name", collider.name},
                 {"friction", collider.friction},
                 {"static_friction", collider.static_friction}};
    switch (collider.shape) {
      case ColliderShape::plane:
        item["point"] = to_json(collider.center);
        item["normal"] = to_json(collider.normal);
        item["half_size"] = collider.plane_half_size;
        break;
      case ColliderShape::sphere:
        item["center"] = to_json(collider.center);
        item["radius"] = collider.radius;
        break;
      case ColliderShape::box:
        item["center"] = to_json(collider.center);
        item["half_extents"] = to_json(collider.half_extents);
        break;
      case ColliderShape::capsule:
      case ColliderShape::cylinder:
        item["center"] = to_json(collider.center);
        item["axis"] = to_json(collider.axis);
        item["radius"] = collider.radius;
        item["half_length"] = collider.half_length;
        if (collider.shape == ColliderShape::cylinder) item["capped"] = collider.capped;
        break;
      case ColliderShape::mesh:
        item["obj"] = collider.obj_file;
        break;
    }
    item["motion"] = {{"velocity", to_json(collider.motion.velocity)},
                      {"pivot", to_json(collider.motion.pivot)},
                      {"axis", to_json(collider.motion.axis)},
                      {"angular_velocity_degrees", collider.motion.angular_velocity * 180.0 / pi}};
    document["colliders"].push_back(item);
  }
  json view = {{"yaw_degrees", scene.view.yaw_degrees},
               {"pitch_degrees", scene.view.pitch_degrees},
               {"show", scene.view.show},
               {"impulse_scale", scene.view.impulse_scale},
               {"max_arrow_length", scene.view.max_arrow_length}};
  if (scene.view.has_target) view["target"] = to_json(scene.view.target);
  if (scene.view.distance > 0.0) view["distance"] = scene.view.distance;
  document["view"] = view;
  return document;
}

json simulated_part(json resolved_scene) {
  resolved_scene.erase("view");
  return resolved_scene;
}

}  // namespace weft
