#include "render/renderer.hpp"

#include <glad/gl.h>

#include <cassert>

#include "core/triangle_mesh.hpp"

namespace weft {

Renderer::Renderer(const std::string& shader_dir)
    : mesh_program_(shader_dir + "/mesh.vert", shader_dir + "/mesh.frag"),
      background_program_(shader_dir + "/background.vert", shader_dir + "/background.frag") {
  glGenVertexArrays(1, &empty_vertex_array_);
}

Renderer::~Renderer() { glDeleteVertexArrays(1, &empty_vertex_array_); }

MeshHandle Renderer::add_mesh(const Triangles& triangles, const Positions& positions,
                              const SurfaceStyle& style) {
  const int num_vertices = static_cast<int>(positions.cols());
  meshes_.push_back({GpuMesh(triangles, num_vertices), triangles, style, Eigen::Matrix4f::Identity(),
                     Eigen::Matrix3Xf(3, num_vertices), Eigen::Matrix3Xf(3, num_vertices)});
  const MeshHandle handle = static_cast<MeshHandle>(meshes_.size()) - 1;
  update_positions(handle, positions);
  return handle;
}

void Renderer::update_positions(MeshHandle mesh, const Positions& positions) {
  Entry& entry = meshes_.at(static_cast<size_t>(mesh));
  assert(positions.cols() == entry.positions.cols());
  entry.positions = positions.cast<float>();
  entry.normals = vertex_normals(positions, entry.triangles).cast<float>();
  entry.gpu.upload(entry.positions, entry.normals);
}

void Renderer::set_transform(MeshHandle mesh, const Eigen::Isometry3d& transform) {
  meshes_.at(static_cast<size_t>(mesh)).model = transform.matrix().cast<float>();
}

void Renderer::clear() { meshes_.clear(); }

void Renderer::draw(const OrbitCamera& camera, int framebuffer_width, int framebuffer_height) const {
  glViewport(0, 0, framebuffer_width, framebuffer_height);
  glClearColor(background_bottom.x(), background_bottom.y(), background_bottom.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Background first, without depth, so meshes cover it.
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  background_program_.use();
  background_program_.set("u_top_color", background_top);
  background_program_.set("u_bottom_color", background_bottom);
  glBindVertexArray(empty_vertex_array_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);

  if (framebuffer_height <= 0 || meshes_.empty()) return;
  const double aspect = static_cast<double>(framebuffer_width) / framebuffer_height;
  const Eigen::Matrix4f view = camera.view_matrix();
  // A key light just above and left of the camera, following it as it orbits, so whatever faces
  // the camera is lit.
  const Eigen::Vector3f right = view.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3f up = view.block<1, 3>(1, 0).transpose();
  const Eigen::Vector3f backward = view.block<1, 3>(2, 0).transpose();
  const Eigen::Vector3f light_dir = (-0.3f * right + 0.65f * up + 0.7f * backward).normalized();

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_MULTISAMPLE);
  mesh_program_.use();
  mesh_program_.set("u_view", view);
  mesh_program_.set("u_projection", camera.projection_matrix(aspect));
  mesh_program_.set("u_eye", Eigen::Vector3f(camera.eye().cast<float>()));
  mesh_program_.set("u_light_dir", light_dir);
  for (const Entry& entry : meshes_) {
    mesh_program_.set("u_model", entry.model);
    mesh_program_.set("u_front_color", entry.style.front_color);
    mesh_program_.set("u_back_color", entry.style.back_color);
    mesh_program_.set("u_specular", entry.style.specular);
    mesh_program_.set("u_shininess", entry.style.shininess);
    mesh_program_.set("u_checker_size", entry.style.checker_size);
    entry.gpu.draw();
  }
  glDisable(GL_DEPTH_TEST);
}

}  // namespace weft
