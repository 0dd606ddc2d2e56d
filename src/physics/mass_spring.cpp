#include "physics/mass_spring.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace weft {

const char* to_string(SpringKind kind) {
  switch (kind) {
    case SpringKind::structural:
      return "structural";
    case SpringKind::shear:
      return "shear";
    case SpringKind::bend:
      return "bend";
  }
  return "unknown";
}

namespace {

// Springs collected per kind before they are packed into a SpringSet.
struct SpringLists {
  std::vector<std::pair<int, int>> pairs[spring_kind_count];
  void add(SpringKind kind, int i, int j) { pairs[static_cast<int>(kind)].emplace_back(i, j); }
};

SpringSet pack_springs(const SpringLists& lists, const Positions& rest_positions,
                       const SpringStiffness& params) {
  // A kind with neither stiffness nor damping is left out: a term that is off costs nothing.
  const auto active = [&](int kind) { return params.stiffness[kind] != 0.0 || params.damping[kind] != 0.0; };
  int total = 0;
  for (int kind = 0; kind < spring_kind_count; ++kind) {
    if (active(kind)) total += static_cast<int>(lists.pairs[kind].size());
  }
  SpringSet springs;
  springs.vertices.resize(2, total);
  springs.rest_length.resize(total);
  springs.stiffness.resize(total);
  springs.damping.resize(total);
  int s = 0;
  for (int kind = 0; kind < spring_kind_count; ++kind) {
    springs.kind_begin[kind] = s;
    if (!active(kind)) continue;
    for (const auto& [i, j] : lists.pairs[kind]) {
      springs.vertices.col(s) << i, j;
      springs.rest_length[s] = (rest_positions.col(j) - rest_positions.col(i)).norm();
      springs.stiffness[s] = params.stiffness[kind];
      springs.damping[s] = params.damping[kind];
      ++s;
    }
  }
  springs.kind_begin[spring_kind_count] = s;
  return springs;
}

}  // namespace

SpringSet make_lattice_springs(int nx, int ny, GridTriangulation triangulation,
                               const Positions& rest_positions, const SpringStiffness& params) {
  SpringLists lists;
  const auto index = [nx](int i, int j) { return j * nx + i; };
  // Structural: lattice neighbours along x and y.
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) lists.add(SpringKind::structural, index(i, j), index(i + 1, j));
      if (j + 1 < ny) lists.add(SpringKind::structural, index(i, j), index(i, j + 1));
    }
  }
  // Shear: both diagonals of every quad, or the four half-diagonals to a `cross` centre vertex.
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      if (triangulation == GridTriangulation::cross) {
        const int centre = nx * ny + j * (nx - 1) + i;
        lists.add(SpringKind::shear, index(i, j), centre);
        lists.add(SpringKind::shear, index(i + 1, j), centre);
        lists.add(SpringKind::shear, index(i, j + 1), centre);
        lists.add(SpringKind::shear, index(i + 1, j + 1), centre);
      } else {
        lists.add(SpringKind::shear, index(i, j), index(i + 1, j + 1));
        lists.add(SpringKind::shear, index(i + 1, j), index(i, j + 1));
      }
    }
  }
  // Bend: two lattice steps apart along x and y.
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 2 < nx) lists.add(SpringKind::bend, index(i, j), index(i + 2, j));
      if (j + 2 < ny) lists.add(SpringKind::bend, index(i, j), index(i, j + 2));
    }
  }
  return pack_springs(lists, rest_positions, params);
}

SpringSet make_mesh_springs(const MeshTopology& topology, const Positions& rest_positions,
                            const SpringStiffness& params) {
  SpringLists lists;
  for (int e = 0; e < topology.num_edges(); ++e) {
    lists.add(SpringKind::structural, topology.edges(0, e), topology.edges(1, e));
  }
  for (int h = 0; h < topology.num_hinges(); ++h) {
    lists.add(SpringKind::bend, topology.hinges(2, h), topology.hinges(3, h));
  }
  return pack_springs(lists, rest_positions, params);
}

void set_spring_params(SpringSet& springs, SpringKind kind, double stiffness, double damping) {
  const int begin = springs.kind_begin[static_cast<int>(kind)];
  const int count = springs.count(kind);
  springs.stiffness.segment(begin, count).setConstant(stiffness);
  springs.damping.segment(begin, count).setConstant(damping);
}

double spring_energy(const SpringSet& springs, const Positions& x) {
  double energy = 0.0;
  for (int s = 0; s < springs.size(); ++s) {
    const double stretch =
        (x.col(springs.vertices(1, s)) - x.col(springs.vertices(0, s))).norm() - springs.rest_length[s];
    energy += 0.5 * springs.stiffness[s] * stretch * stretch;
  }
  return energy;
}

void add_spring_forces(const SpringSet& springs, const Positions& x, const Positions& v, Positions& force) {
  for (int s = 0; s < springs.size(); ++s) {
    const int i = springs.vertices(0, s);
    const int j = springs.vertices(1, s);
    const Vec3 d = x.col(j) - x.col(i);
    const double length_squared = d.squaredNorm();
    if (length_squared == 0.0) continue;  // direction undefined: no force
    const double length = std::sqrt(length_squared);
    // Elastic: k (|d| - L) d/|d|; damping: gamma ((vj - vi) . d) d / |d|^2 (mass_spring.hpp).
    const double elastic = springs.stiffness[s] * (length - springs.rest_length[s]) / length;
    const double damping = springs.damping[s] * (v.col(j) - v.col(i)).dot(d) / length_squared;
    const Vec3 f_i = (elastic + damping) * d;
    force.col(i) += f_i;
    force.col(j) -= f_i;
  }
}

Mat3 spring_hessian_block(const Vec3& d, double rest_length, double stiffness, bool project_to_psd) {
  const double length = d.norm();
  if (length == 0.0) return stiffness * Mat3::Identity();  // direction undefined: isotropic stiffness
  const Vec3 direction = d / length;
  const Mat3 along = direction * direction.transpose();
  double transverse = 1.0 - rest_length / length;
  if (project_to_psd) transverse = std::max(transverse, 0.0);
  return stiffness * (along + transverse * (Mat3::Identity() - along));
}

double evaluate_springs(const SpringSet& springs, const Positions& x, Positions* gradient, SparseHessian* hessian,
                        int stencil, bool project_to_psd) {
  double energy = 0.0;
  for (int s = 0; s < springs.size(); ++s) {
    const int i = springs.vertices(0, s);
    const int j = springs.vertices(1, s);
    const Vec3 d = x.col(j) - x.col(i);
    const double length = d.norm();
    const double stretch = length - springs.rest_length[s];
    const double k = springs.stiffness[s];
    energy += 0.5 * k * stretch * stretch;
    if (gradient != nullptr && length > 0.0) {
      const Vec3 g = (k * stretch / length) * d;  // dE/dxj
      gradient->col(j) += g;
      gradient->col(i) -= g;
    }
    if (hessian != nullptr) {
      const Mat3 block = spring_hessian_block(d, springs.rest_length[s], k, project_to_psd);
      Matrix6d element;
      element << block, -block, -block, block;
      hessian->add_element<2>(stencil, s, element);
    }
  }
  return energy;
}

double evaluate_spring_damping(const SpringSet& springs, const Positions& x_start, const Positions& x, double h,
                               Positions* gradient, SparseHessian* hessian, int stencil) {
  double energy = 0.0;
  for (int s = 0; s < springs.size(); ++s) {
    const double gamma = springs.damping[s];
    if (gamma == 0.0) continue;
    const int i = springs.vertices(0, s);
    const int j = springs.vertices(1, s);
    const Vec3 d_start = x_start.col(j) - x_start.col(i);
    const double length = d_start.norm();
    if (length == 0.0) continue;
    const Vec3 u = d_start / length;
    const double relative = (x.col(j) - x_start.col(j) - x.col(i) + x_start.col(i)).dot(u);
    energy += 0.5 * gamma / h * relative * relative;
    if (gradient != nullptr) {
      const Vec3 g = (gamma / h * relative) * u;
      gradient->col(j) += g;
      gradient->col(i) -= g;
    }
    if (hessian != nullptr) {
      const Mat3 block = (gamma / h) * u * u.transpose();
      Matrix6d element;
      element << block, -block, -block, block;
      hessian->add_element<2>(stencil, s, element);
    }
  }
  return energy;
}

}  // namespace weft
