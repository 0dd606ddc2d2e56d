#include "render/gpu_mesh.hpp"

#include <glad/gl.h>

#include <cassert>
#include <utility>
#include <vector>

namespace weft {

namespace {

// A float vec3 attribute at `location` streamed from `buffer`.
// A float attribute of `size` components at `location` streamed from `buffer`, zero-filled.
void define_attribute(GLuint location, GLuint buffer, int size, int num_vertices) {
  const std::vector<float> zeros(static_cast<size_t>(size) * static_cast<size_t>(num_vertices), 0.0f);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(zeros.size() * sizeof(float)), zeros.data(),
               GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, size * static_cast<GLsizei>(sizeof(float)), nullptr);
}

}  // namespace

GpuMesh::GpuMesh(const Triangles& triangles, int num_vertices)
    : num_vertices_(num_vertices), num_indices_(static_cast<int>(triangles.size())) {
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &position_buffer_);
  glGenBuffers(1, &normal_buffer_);
  glGenBuffers(1, &scalar_buffer_);
  glGenBuffers(1, &index_buffer_);
  glBindVertexArray(vertex_array_);
  define_attribute(0, position_buffer_, 3, num_vertices_);
  define_attribute(1, normal_buffer_, 3, num_vertices_);
  define_attribute(2, scalar_buffer_, 1, num_vertices_);
  // Triangles are 3 x M column-major ints: already the index order GL wants.
  const Eigen::Matrix<unsigned int, 3, Eigen::Dynamic> indices = triangles.cast<unsigned int>();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(sizeof(unsigned int)) * num_indices_,
               indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
}

GpuMesh::~GpuMesh() { release(); }

GpuMesh::GpuMesh(GpuMesh&& other) noexcept
    : vertex_array_(std::exchange(other.vertex_array_, 0)),
      position_buffer_(std::exchange(other.position_buffer_, 0)),
      normal_buffer_(std::exchange(other.normal_buffer_, 0)),
      scalar_buffer_(std::exchange(other.scalar_buffer_, 0)),
      index_buffer_(std::exchange(other.index_buffer_, 0)),
      num_vertices_(other.num_vertices_),
      num_indices_(other.num_indices_) {}

GpuMesh& GpuMesh::operator=(GpuMesh&& other) noexcept {
  if (this != &other) {
    release();
    vertex_array_ = std::exchange(other.vertex_array_, 0);
    position_buffer_ = std::exchange(other.position_buffer_, 0);
    normal_buffer_ = std::exchange(other.normal_buffer_, 0);
    scalar_buffer_ = std::exchange(other.scalar_buffer_, 0);
    index_buffer_ = std::exchange(other.index_buffer_, 0);
    num_vertices_ = other.num_vertices_;
    num_indices_ = other.num_indices_;
  }
  return *this;
}

void GpuMesh::release() {
  if (vertex_array_ == 0) return;
  const GLuint buffers[] = {position_buffer_, normal_buffer_, scalar_buffer_, index_buffer_};
  glDeleteBuffers(4, buffers);
  glDeleteVertexArrays(1, &vertex_array_);
  vertex_array_ = position_buffer_ = normal_buffer_ = scalar_buffer_ = index_buffer_ = 0;
}

void GpuMesh::upload(const Eigen::Matrix3Xf& positions, const Eigen::Matrix3Xf& normals) {
  assert(positions.cols() == num_vertices_ && normals.cols() == num_vertices_);
  const GLsizeiptr bytes = static_cast<GLsizeiptr>(3 * sizeof(float)) * num_vertices_;
  glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, positions.data());
  glBindBuffer(GL_ARRAY_BUFFER, normal_buffer_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, normals.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GpuMesh::upload_scalars(const Eigen::VectorXf& scalars) {
  assert(scalars.size() == num_vertices_);
  glBindBuffer(GL_ARRAY_BUFFER, scalar_buffer_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(sizeof(float)) * num_vertices_, scalars.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GpuMesh::draw() const {
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, num_indices_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace weft
