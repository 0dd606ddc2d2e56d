#include "io/scene_builder.hpp"

#include <filesystem>

#include "core/error.hpp"
#include "core/topology.hpp"
#include "io/obj_io.hpp"

namespace weft {

namespace {

// The cloth's rest mesh: a generated grid, or the OBJ file resolved against the scene's folder.
TriangleMesh make_rest_mesh(const ClothDesc& desc, const SceneDesc& scene, const std::string& path) {
  TriangleMesh mesh;
  if (desc.obj_file.empty()) {
    mesh = make_grid(desc.grid_nx, desc.grid_ny, desc.grid_width, desc.grid_height, desc.triangulation);
  } else {
    std::filesystem::path file(desc.obj_file);
    if (file.is_relative()) file = std::filesystem::path(scene.source_file).parent_path() / file;
    try {
      mesh = read_obj(file.string());
    } catch (const IoError& error) {
      throw SceneError(scene.source_file, path + "/obj", error.what());
    }
  }
  transform_positions(mesh.positions, rotation_from_euler_degrees(desc.rotation_degrees), desc.scale,
                      desc.translation);
  return mesh;
}

// Lumped masses: each triangle gives a third of its mass (density x area) to each of its corners.
Eigen::VectorXd lumped_masses(const TriangleMesh& mesh, const ClothDesc& desc, const std::string& file,
                              const std::string& path) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a = mesh.positions.col(mesh.triangles(0, t));
    const Vec3 b = mesh.positions.col(mesh.triangles(1, t));
    const Vec3 c = mesh.positions.col(mesh.triangles(2, t));
    const double third = desc.density * 0.5 * (b - a).cross(c - a).norm() / 3.0;
    for (int k = 0; k < 3; ++k) mass[mesh.triangles(k, t)] += third;
  }
  if (desc.mass > 0.0) mass *= desc.mass / mass.sum();
  for (int i = 0; i < mass.size(); ++i) {
    if (!(mass[i] > 0.0)) {
      throw SceneError(file, path, "vertex " + std::to_string(i) +
                                       " belongs to no triangle of non-zero area, so it has no mass");
    }
  }
  return mass;
}

// Vertex indices of the named corners and edges of an nx x ny lattice (row j = 0 is the bottom).
std::vector<int> named_grid_pins(const ClothDesc& desc) {
  const int nx = desc.grid_nx;
  const int ny = desc.grid_ny;
  std::vector<int> pins;
  for (const std::string& corner : desc.pin_corners) {
    const int i = corner.find("right") != std::string::npos ? nx - 1 : 0;
    const int j = corner.find("top") != std::string::npos ? ny - 1 : 0;
    pins.push_back(j * nx + i);
  }
  for (const std::string& edge : desc.pin_edges) {
    if (edge == "bottom" || edge == "top") {
      const int j = edge == "top" ? ny - 1 : 0;
      for (int i = 0; i < nx; ++i) pins.push_back(j * nx + i);
    } else {
      const int i = edge == "right" ? nx - 1 : 0;
      for (int j = 0; j < ny; ++j) pins.push_back(j * nx + i);
    }
  }
  return pins;
}

Cloth build_cloth(const ClothDesc& desc, const SceneDesc& scene, int index) {
  const std::string path = "/cloths/" + std::to_string(index);
  TriangleMesh mesh = make_rest_mesh(desc, scene, path);

  ClothModel model;
  model.name = desc.name;
  model.thickness = desc.thickness;
  model.mass_damping = desc.mass_damping;
  model.mass = lumped_masses(mesh, desc, scene.source_file, desc.obj_file.empty() ? path + "/grid" : path + "/obj");

  SpringStiffness params;
  const SpringParams* kinds[spring_kind_count] = {&desc.structural, &desc.shear, &desc.bend};
  for (int k = 0; k < spring_kind_count; ++k) {
    params.stiffness[k] = kinds[k]->stiffness;
    params.damping[k] = kinds[k]->damping;
  }
  if (desc.obj_file.empty()) {
    model.grid_nx = desc.grid_nx;
    model.grid_ny = desc.grid_ny;
    model.springs = make_lattice_springs(desc.grid_nx, desc.grid_ny, desc.triangulation, mesh.positions, params);
  } else {
    model.springs = make_mesh_springs(build_topology(mesh.triangles, mesh.num_vertices()), mesh.positions, params);
  }

  // Pins: inverse mass 0, so the integrator never moves them.
  model.inverse_mass = model.mass.cwiseInverse();
  for (size_t k = 0; k < desc.pin_vertices.size(); ++k) {
    const int vertex = desc.pin_vertices[k];
    if (vertex >= mesh.num_vertices()) {
      throw SceneError(scene.source_file, path + "/pins/vertices/" + std::to_string(k),
                       "expected a vertex index below " + std::to_string(mesh.num_vertices()) + ", got " +
                           std::to_string(vertex));
    }
    model.inverse_mass[vertex] = 0.0;
  }
  for (int vertex : named_grid_pins(desc)) model.inverse_mass[vertex] = 0.0;

  model.triangles = std::move(mesh.triangles);
  model.uvs = std::move(mesh.uvs);
  model.rest_positions = std::move(mesh.positions);
  return make_cloth(std::move(model));
}

}  // namespace

World build_world(const SceneDesc& scene) {
  World world;
  world.settings.integrator = scene.integrator;
  world.settings.time_step = frame_schedule(scene.fps, scene.time_step).time_step;
  world.settings.substeps = scene.substeps;
  world.settings.gravity = scene.gravity;
  world.settings.implicit = scene.implicit;
  world.settings.adaptive = scene.adaptive;
  for (size_t k = 0; k < scene.cloths.size(); ++k) {
    world.add_cloth(build_cloth(scene.cloths[k], scene, static_cast<int>(k)));
  }
  for (const Collider& collider : scene.colliders) world.add_collider(collider);
  return world;
}

}  // namespace weft
