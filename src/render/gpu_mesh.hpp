#pragma once
// A triangle mesh in GPU buffers: fixed indices, positions and normals replaced as often as wanted.
// Needs a current GL context.
#include <Eigen/Core>

#include "core/math.hpp"

namespace weft {

class GpuMesh {
 public:
  // Allocates buffers for `num_vertices` vertices and uploads the triangles once.
  GpuMesh(const Triangles& triangles, int num_vertices);
  ~GpuMesh();
  GpuMesh(GpuMesh&& other) noexcept;
  GpuMesh& operator=(GpuMesh&& other) noexcept;
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  // Replaces every vertex's position and normal (3 x num_vertices each).
  void upload(const Eigen::Matrix3Xf& positions, const Eigen::Matrix3Xf& normals);
  void draw() const;

 private:
  void release();

  unsigned int vertex_array_ = 0;
  unsigned int position_buffer_ = 0;
  unsigned int normal_buffer_ = 0;
  unsigned int index_buffer_ = 0;
  int num_vertices_ = 0;
  int num_indices_ = 0;
};

}  // namespace weft
