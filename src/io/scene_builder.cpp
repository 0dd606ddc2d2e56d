#include "io/scene_builder.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "collision/collider_push_out.hpp"
#include "core/error.hpp"
#include "core/topology.hpp"
#include "io/obj_io.hpp"

namespace weft {

namespace {

// An OBJ file named in the scene, resolved against the scene file's folder.
std::string resolve_obj_path(const std::string& obj_file, const SceneDesc& scene) {
  std::filesystem::path file(obj_file);
  if (file.is_relative()) file = std::filesystem::path(scene.source_file).parent_path() / file;
  return file.string();
}

// The cloth's rest mesh: a generated grid, or the OBJ file resolved against the scene's folder.
TriangleMesh make_rest_mesh(const ClothDesc& desc, const SceneDesc& scene, const std::string& path) {
  TriangleMesh mesh;
  if (desc.sphere) {
    mesh = make_uv_sphere(desc.sphere_radius, desc.sphere_slices, desc.sphere_stacks);
  } else if (desc.obj_file.empty()) {
    mesh = make_grid(desc.grid_nx, desc.grid_ny, desc.grid_width, desc.grid_height, desc.triangulation);
  } else {
    try {
      mesh = read_obj(resolve_obj_path(desc.obj_file, scene));
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

// Vertex indices of a pin selection: explicit indices (checked against the vertex count), then
// the named corners and edges of an nx x ny lattice (row j = 0 is the bottom).
std::vector<int> selected_vertices(const PinSelection& selection, const ClothDesc& desc, int num_vertices,
                                   const std::string& file, const std::string& path) {
  const int nx = desc.grid_nx;
  const int ny = desc.grid_ny;
  std::vector<int> pins;
  for (size_t k = 0; k < selection.vertices.size(); ++k) {
    const int vertex = selection.vertices[k];
    if (vertex >= num_vertices) {
      throw SceneError(file, path + "/vertices/" + std::to_string(k),
                       "expected a vertex index below " + std::to_string(num_vertices) + ", got " +
                           std::to_string(vertex));
    }
    pins.push_back(vertex);
  }
  for (const std::string& corner : selection.corners) {
    const int i = corner.find("right") != std::string::npos ? nx - 1 : 0;
    const int j = corner.find("top") != std::string::npos ? ny - 1 : 0;
    pins.push_back(j * nx + i);
  }
  for (const std::string& edge : selection.edges) {
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

// "the edge between vertices 2 and 5 is in 3 triangles (1, 4, 7) ...", numbered as in the OBJ file.
std::string describe_non_manifold_edge(const Triangles& triangles, const MeshTopology& topology, int edge) {
  const int a = topology.edges(0, edge), b = topology.edges(1, edge);
  std::string list;
  int count = 0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const auto corner = [&](int v) { return (triangles.col(t).array() == v).any(); };
    if (corner(a) && corner(b)) {
      list += (count++ ? ", " : "") + std::to_string(t + 1);
    }
  }
  return "the edge between vertices " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " is in " +
         std::to_string(count) + " triangles (" + list +
         "); expected a manifold cloth, each edge in one or two triangles";
}

// The first triangle of a collider mesh with no area (collinear corners), or -1. A collider pushes
// cloth out along its triangles' normals, which such a triangle does not have.
int first_zero_area_triangle(const TriangleMesh& mesh) {
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a = mesh.positions.col(mesh.triangles(0, t));
    const Vec3 b = mesh.positions.col(mesh.triangles(1, t));
    const Vec3 c = mesh.positions.col(mesh.triangles(2, t));
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // Relative to the longest edge, so the test does not depend on the mesh's units.
    if ((b - a).cross(c - a).norm() <= 1e-12 * longest) return t;
  }
  return -1;
}

Cloth build_cloth(const ClothDesc& desc, const SceneDesc& scene, int index) {
  const std::string path = "/cloths/" + std::to_string(index);
  TriangleMesh mesh = make_rest_mesh(desc, scene, path);

  // A contact thickness near the cloth's own size puts every part of it in contact with most
  // others (vertex-face pairs grow as the square of the vertex count): refused, the step would not end.
  const double size = (mesh.positions.rowwise().maxCoeff() - mesh.positions.rowwise().minCoeff()).norm();
  if (desc.thickness > max_thickness_fraction * size) {
    std::ostringstream message;
    message << std::setprecision(4) << "expected a contact thickness of at most "
            << max_thickness_fraction * size << " m (" << 100.0 * max_thickness_fraction
            << "% of the cloth's size, its rest bounding-box diagonal " << size << " m), got "
            << desc.thickness;
    throw SceneError(scene.source_file, path + "/thickness", message.str());
  }

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
  const MeshTopology topology = build_topology(mesh.triangles, mesh.num_vertices());
  if (!topology.non_manifold_edges.empty()) {
    throw SceneError(
        scene.source_file, path + "/obj",
        resolve_obj_path(desc.obj_file, scene) + ": " +
            describe_non_manifold_edge(mesh.triangles, topology, topology.non_manifold_edges[0]));
  }
  const bool grid = !desc.sphere && desc.obj_file.empty();
  if (grid) {
    model.grid_nx = desc.grid_nx;
    model.grid_ny = desc.grid_ny;
    model.springs = make_lattice_springs(desc.grid_nx, desc.grid_ny, desc.triangulation, mesh.positions, params);
  } else {
    model.springs = make_mesh_springs(topology, mesh.positions, params);
  }

  // Continuum terms the scene turned on.
  if (desc.membrane) {
    try {
      model.membrane = make_membrane_term(mesh.triangles, mesh.positions, desc.membrane_material, desc.yield_strain,
                                          desc.plastic_flow);
    } catch (const std::invalid_argument& error) {
      throw SceneError(scene.source_file, path + "/membrane", error.what());
    }
  }
  if (desc.bending) {
    try {
      model.bending = make_bending_term(topology, mesh.positions, desc.bending_stiffness, desc.bending_model);
    } catch (const std::invalid_argument& error) {
      throw SceneError(scene.source_file, path + "/bending/model", error.what());
    }
  }
  model.air_drag.normal_coefficient = desc.normal_drag;
  model.air_drag.tangential_coefficient = desc.tangential_drag;
  model.air_drag.wind = scene.wind;
  if (desc.pressure) {
    if (!topology.boundary_edges.empty() || !topology.non_manifold_edges.empty()) {
      throw SceneError(scene.source_file, path + "/pressure",
                       "pressure needs a closed surface, but the mesh has " +
                           std::to_string(topology.boundary_edges.size()) + " boundary edges");
    }
    model.pressure.enabled = true;
    model.pressure.law.bulk_modulus = desc.bulk_modulus;
    model.pressure.law.pressure_scale = desc.pressure_scale;
    model.pressure.law.rest_volume = enclosed_volume(mesh.triangles, mesh.positions);
    if (!(model.pressure.law.rest_volume > 0.0)) {
      throw SceneError(scene.source_file, path + "/pressure",
                       "the closed mesh encloses no positive volume (are its triangles facing inwards?)");
    }
  }

  // Pins, fixed and moving: inverse mass 0, so the integrators never move them.
  model.inverse_mass = model.mass.cwiseInverse();
  for (int vertex : selected_vertices(desc.pins, desc, mesh.num_vertices(), scene.source_file, path + "/pins")) {
    model.inverse_mass[vertex] = 0.0;
  }
  for (size_t g = 0; g < desc.moving_pins.size(); ++g) {
    const MovingPinDesc& moving = desc.moving_pins[g];
    PinScript script;
    script.vertices = selected_vertices(moving.selection, desc, mesh.num_vertices(), scene.source_file,
                                        path + "/moving_pins/" + std::to_string(g));
    script.start_positions.resize(3, static_cast<Eigen::Index>(script.vertices.size()));
    for (size_t k = 0; k < script.vertices.size(); ++k) {
      script.start_positions.col(static_cast<Eigen::Index>(k)) = mesh.positions.col(script.vertices[k]);
      model.inverse_mass[script.vertices[k]] = 0.0;
    }
    script.velocity = moving.velocity;
    script.center = moving.center;
    script.axis = moving.axis;
    script.angular_velocity = moving.angular_velocity_degrees * pi / 180.0;
    model.scripted_pins.push_back(std::move(script));
  }

  model.triangles = std::move(mesh.triangles);
  model.uvs = std::move(mesh.uvs);
  model.rest_positions = std::move(mesh.positions);
  Cloth cloth = make_cloth(std::move(model));
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    if (cloth.model.inverse_mass[i] > 0.0) cloth.state.v.col(i) = desc.initial_velocity;
  }
  return cloth;
}

// Bytes a run needs per cloth vertex, measured (max RSS over a frame, 65k to 1M vertices): about
// 0.7 kB to build the cloth, 1.3 kB stepping explicitly, 3.5 kB with implicit Euler's Hessian and
// factorisation. Slightly under those, so only a scene sure not to fit is refused.
double bytes_per_vertex(IntegratorKind integrator) {
  return integrator == IntegratorKind::implicit_euler ? 3000.0 : 1200.0;
}

// The memory this process may use: physical memory, or less under `ulimit -v` / `ulimit -d`.
double usable_memory_bytes() {
  double bytes =
      static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
  for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
    rlimit limit{};
    if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
      bytes = std::min(bytes, static_cast<double>(limit.rlim_cur));
    }
  }
  return bytes;
}

// Refuses a scene whose generated cloths (grids, spheres) cannot fit in memory, before allocating
// them: a 4096 x 4096 grid otherwise ends in std::bad_alloc halfway through building.
void check_memory(const SceneDesc& scene) {
  double vertices = 0.0;
  int largest = -1;
  double largest_vertices = 0.0;
  for (size_t k = 0; k < scene.cloths.size(); ++k) {
    const ClothDesc& cloth = scene.cloths[k];
    if (!cloth.obj_file.empty()) continue;  // an OBJ file is as large as its mesh: read, not guessed
    const double count = cloth.sphere
                             ? static_cast<double>(cloth.sphere_slices) * (cloth.sphere_stacks - 1) + 2
                             : static_cast<double>(cloth.grid_nx) * cloth.grid_ny;
    vertices += count;
    if (count > largest_vertices) {
      largest = static_cast<int>(k);
      largest_vertices = count;
    }
  }
  const double needed = vertices * bytes_per_vertex(scene.integrator);
  const double usable = usable_memory_bytes();
  if (largest < 0 || needed <= usable) return;
  const ClothDesc& cloth = scene.cloths[largest];
  std::ostringstream message;
  message << std::setprecision(3) << "the scene needs about " << needed / 1e9 << " GB ("
          << static_cast<long long>(vertices) << " cloth vertices at about "
          << bytes_per_vertex(scene.integrator) / 1e3 << " kB each), more than the " << usable / 1e9
          << " GB this process may use (physical memory, or ulimit -v); expected a smaller "
          << (cloth.sphere ? "sphere" : "resolution") << " or a machine with more memory";
  throw SceneError(scene.source_file,
                   "/cloths/" + std::to_string(largest) + (cloth.sphere ? "/sphere" : "/grid/resolution"),
                   message.str());
}

// A pinned vertex inside a collider is a tangle untangling cannot undo (it cannot move the pin):
// refused, naming the cloth, the vertex and the collider, where untangling is on.
void refuse_pins_inside_colliders(const SceneDesc& scene, const World& world) {
  if (!scene.collision.enabled || !scene.collision.untangle) return;
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    const Cloth& cloth = world.cloths()[c];
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      const Collider& collider = world.colliders()[k];
      if (!collider_has_inside(collider)) continue;
      for (Eigen::Index v = 0; v < cloth.state.x.cols(); ++v) {
        if (cloth.model.inverse_mass(v) != 0.0) continue;
        const double distance = signed_distance_at(collider, cloth.state.x.col(v), 0.0);
        if (!(distance < 0.0)) continue;
        std::ostringstream message;
        message << std::setprecision(3) << "vertex " << v << " of cloth '" << scene.cloths[c].name
                << "' is pinned " << -distance * 100.0 << " cm inside collider '" << collider.name
                << "' (/colliders/" << k
                << "); untangling cannot move a pinned vertex out: expected the pin outside the collider"
                   " (move the pin or the collider, or set collision.untangle to false)";
        throw SceneError(scene.source_file, "/cloths/" + std::to_string(c) + "/pins", message.str());
      }
    }
  }
}

}  // namespace

World build_world(const SceneDesc& scene) {
  check_memory(scene);
  World world;
  world.settings.integrator = scene.integrator;
  world.settings.time_step = frame_schedule(scene.fps, scene.time_step).time_step;
  world.settings.substeps = scene.substeps;
  world.settings.max_travel_edges = scene.max_travel_edges;
  world.settings.gravity = scene.gravity;
  world.settings.implicit = scene.implicit;
  world.settings.xpbd = scene.xpbd;
  world.settings.adaptive = scene.adaptive;
  world.settings.collision = scene.collision;
  for (size_t k = 0; k < scene.cloths.size(); ++k) {
    world.add_cloth(build_cloth(scene.cloths[k], scene, static_cast<int>(k)), scene.cloths[k].contact);
  }
  for (size_t k = 0; k < scene.colliders.size(); ++k) {
    Collider collider = scene.colliders[k];
    const bool from_obj = collider.shape == ColliderShape::mesh;
    if (from_obj) {
      // OBJ files are resolved against the scene file's folder, like cloth meshes.
      const std::string file = resolve_obj_path(collider.obj_file, scene);
      const std::string path = "/colliders/" + std::to_string(k) + "/obj";
      try {
        collider.mesh = read_obj(file);
      } catch (const IoError& error) {
        throw SceneError(scene.source_file, path, error.what());
      }
      if (collider.mesh.num_triangles() == 0) throw SceneError(scene.source_file, path, "the OBJ file has no triangles");
      if (const int t = first_zero_area_triangle(collider.mesh); t >= 0) {
        const Vec3i corners = collider.mesh.triangles.col(t);
        throw SceneError(
            scene.source_file, path,
            file + ": triangle " + std::to_string(t + 1) + " (vertices " + std::to_string(corners[0] + 1) +
                ", " + std::to_string(corners[1] + 1) + ", " + std::to_string(corners[2] + 1) +
                ") has zero area; expected collider triangles with three corners not on one line");
      }
    }
    try {
      world.add_collider(std::move(collider));
    } catch (const std::invalid_argument& error) {
      const std::string path = "/colliders/" + std::to_string(k) + (from_obj ? "/obj" : "");
      throw SceneError(scene.source_file, path, error.what());
    }
  }
  refuse_pins_inside_colliders(scene, world);
  return world;
}

}  // namespace weft
