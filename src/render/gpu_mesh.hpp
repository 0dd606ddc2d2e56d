#pragma once
// A triangle mesh in GPU buffers: fixed indices; positions, normals and one scalar per vertex (e.g.
// strain for a heat map) replaced as often as wanted.
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
  // Replaces every vertex's scalar (num_vertices); zero until set.
  void upload_scalars(const Eigen::VectorXf& scalars);
  void draw() const;
  int num_vertices() const { return num_vertices_; }

 private:
  void release();

  unsigned int vertex_array_ = 0;
  unsigned int position_buffer_ = 0;
  unsigned int normal_buffer_ = 0;
  unsigned int scalar_buffer_ = 0;
  unsigned int index_buffer_ = 0;
  int num_vertices_ = 0;
  int num_indices_ = 0;
};

}  // namespace weft
