#include "render/renderer.hpp"

#include <glad/gl.h>

#include <cassert>

#include "core/triangle_mesh.hpp"
#include "render/render_error.hpp"

namespace weft {

namespace {

constexpr int overlay_floats_per_vertex = 7;  // position, colour, point size

void push_overlay_vertex(std::vector<float>& out, const Vec3& position, const Color& color, float size) {
  out.insert(out.end(), {static_cast<float>(position.x()), static_cast<float>(position.y()),
                         static_cast<float>(position.z()), color.x(), color.y(), color.z(), size});
}

}  // namespace

std::unique_ptr<Renderer::Programs> Renderer::load_programs(const std::string& shader_dir) {
  return std::unique_ptr<Programs>(new Programs{
      ShaderProgram(shader_dir + "/mesh.vert", shader_dir + "/mesh.frag"),
      ShaderProgram(shader_dir + "/background.vert", shader_dir + "/background.frag"),
      ShaderProgram(shader_dir + "/overlay.vert", shader_dir + "/overlay.frag")});
}

Renderer::Renderer(const std::string& shader_dir) : shader_dir_(shader_dir), programs_(load_programs(shader_dir)) {
  glGenVertexArrays(1, &empty_vertex_array_);
  glGenVertexArrays(1, &overlay_vertex_array_);
  glGenBuffers(1, &overlay_buffer_);
  glBindVertexArray(overlay_vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, overlay_buffer_);
  const GLsizei stride = overlay_floats_per_vertex * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(6 * sizeof(float)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

Renderer::~Renderer() {
  meshes_.clear();
  glDeleteBuffers(1, &overlay_buffer_);
  glDeleteVertexArrays(1, &overlay_vertex_array_);
  glDeleteVertexArrays(1, &empty_vertex_array_);
}

std::string Renderer::reload_shaders() {
  try {
    programs_ = load_programs(shader_dir_);
  } catch (const RenderError& error) {
    return error.what();
  }
  return {};
}

MeshHandle Renderer::add_mesh(const Triangles& triangles, const Positions& positions,
                              const SurfaceStyle& style) {
  const int num_vertices = static_cast<int>(positions.cols());
  meshes_.push_back({GpuMesh(triangles, num_vertices), triangles, style, MeshDisplay{}, Eigen::Matrix4f::Identity(),
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

void Renderer::update_scalars(MeshHandle mesh, const Eigen::VectorXd& scalars) {
  meshes_.at(static_cast<size_t>(mesh)).gpu.upload_scalars(scalars.cast<float>());
}

void Renderer::set_transform(MeshHandle mesh, const Eigen::Isometry3d& transform) {
  meshes_.at(static_cast<size_t>(mesh)).model = transform.matrix().cast<float>();
}

void Renderer::set_display(MeshHandle mesh, const MeshDisplay& display) {
  meshes_.at(static_cast<size_t>(mesh)).display = display;
}

void Renderer::clear() { meshes_.clear(); }

void Renderer::draw(const OrbitCamera& camera, int framebuffer_width, int framebuffer_height,
                    const DebugOverlay& overlay, float pixel_scale) {
  glViewport(0, 0, framebuffer_width, framebuffer_height);
  glClearColor(background_bottom.x(), background_bottom.y(), background_bottom.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Background first, without depth, so meshes cover it.
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  programs_->background.use();
  programs_->background.set("u_top_color", background_top);
  programs_->background.set("u_bottom_color", background_bottom);
  glBindVertexArray(empty_vertex_array_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);

  if (framebuffer_height <= 0) return;
  const double aspect = static_cast<double>(framebuffer_width) / framebuffer_height;
  const Eigen::Matrix4f view = camera.view_matrix();
  const Eigen::Matrix4f projection = camera.projection_matrix(aspect);
  // A key light just above and left of the camera, following it as it orbits, so whatever faces
  // the camera is lit.
  const Eigen::Vector3f right = view.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3f up = view.block<1, 3>(1, 0).transpose();
  const Eigen::Vector3f backward = view.block<1, 3>(2, 0).transpose();
  const Eigen::Vector3f light_dir = (-0.3f * right + 0.65f * up + 0.7f * backward).normalized();

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_MULTISAMPLE);
  const ShaderProgram& mesh_program = programs_->mesh;
  mesh_program.use();
  mesh_program.set("u_view", view);
  mesh_program.set("u_projection", projection);
  mesh_program.set("u_eye", Eigen::Vector3f(camera.eye().cast<float>()));
  mesh_program.set("u_light_dir", light_dir);
  mesh_program.set("u_flat_color", wireframe_color);
  for (const Entry& entry : meshes_) {
    if (!entry.display.visible) continue;
    mesh_program.set("u_model", entry.model);
    mesh_program.set("u_front_color", entry.style.front_color);
    mesh_program.set("u_back_color", entry.style.back_color);
    mesh_program.set("u_specular", entry.style.specular);
    mesh_program.set("u_shininess", entry.style.shininess);
    mesh_program.set("u_checker_size", entry.style.checker_size);
    mesh_program.set("u_color_mode", entry.display.heat_map ? 1 : 0);
    mesh_program.set("u_scalar_range", entry.display.scalar_range);
    // The surface is pushed back a little so its wireframe wins the depth test.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    if (entry.display.cull_front) {
      glEnable(GL_CULL_FACE);
      glCullFace(GL_FRONT);
    }
    entry.gpu.draw();
    glDisable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (entry.display.wireframe) {
      mesh_program.set("u_color_mode", 2);
      glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      entry.gpu.draw();
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
  }
  draw_overlay(overlay, projection * view, pixel_scale);
  glDisable(GL_DEPTH_TEST);
}

void Renderer::draw_overlay(const DebugOverlay& overlay, const Eigen::Matrix4f& view_projection, float pixel_scale) {
  if (overlay.lines.empty() && overlay.points.empty()) return;
  overlay_scratch_.clear();
  overlay_scratch_.reserve(overlay_floats_per_vertex * (2 * overlay.lines.size() + overlay.points.size()));
  for (const OverlayLine& line : overlay.lines) {
    push_overlay_vertex(overlay_scratch_, line.from, line.color, 1.0f);
    push_overlay_vertex(overlay_scratch_, line.to, line.color, 1.0f);
  }
  for (const OverlayPoint& point : overlay.points) push_overlay_vertex(overlay_scratch_, point.position, point.color, point.size);

  glBindBuffer(GL_ARRAY_BUFFER, overlay_buffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(overlay_scratch_.size() * sizeof(float)),
               overlay_scratch_.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, 0);

  const ShaderProgram& program = programs_->overlay;
  program.use();
  program.set("u_view_projection", view_projection);
  program.set("u_depth_bias", 2e-4f);
  program.set("u_pixel_scale", pixel_scale);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glDepthFunc(GL_LEQUAL);
  glBindVertexArray(overlay_vertex_array_);
  const GLsizei line_vertices = static_cast<GLsizei>(2 * overlay.lines.size());
  program.set("u_round_points", 0);
  if (line_vertices > 0) glDrawArrays(GL_LINES, 0, line_vertices);
  // Points on top of lines, and round.
  program.set("u_round_points", 1);
  program.set("u_depth_bias", 1e-3f);
  if (!overlay.points.empty()) glDrawArrays(GL_POINTS, line_vertices, static_cast<GLsizei>(overlay.points.size()));
  glBindVertexArray(0);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glDepthFunc(GL_LESS);
}

}  // namespace weft
