#pragma once
// Mass-spring forces (Provot 1995): f = k (|xj - xi| - L) (xj - xi)/|xj - xi| on vertex i, plus
// damping gamma ((vj - vi) . d) d / |d|^2 with d = xj - xi; structural, shear and bend springs.
#include "core/math.hpp"
#include "core/mesh_generators.hpp"
#include "core/topology.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

enum class SpringKind { structural = 0, shear = 1, bend = 2 };
inline constexpr int spring_kind_count = 3;
const char* to_string(SpringKind kind);

// Springs stored grouped by kind: springs of kind k occupy [kind_begin[k], kind_begin[k + 1]).
struct SpringSet {
  Eigen::Matrix2Xi vertices;       // end vertices (2 x n_springs)
  Eigen::VectorXd rest_length;     // m (n_springs)
  Eigen::VectorXd stiffness;       // N/m (n_springs)
  Eigen::VectorXd damping;         // N s/m (n_springs)
  int kind_begin[spring_kind_count + 1] = {0, 0, 0, 0};

  int size() const { return static_cast<int>(rest_length.size()); }
  int count(SpringKind kind) const {
    return kind_begin[static_cast<int>(kind) + 1] - kind_begin[static_cast<int>(kind)];
  }
};

struct SpringStiffness {
  double stiffness[spring_kind_count] = {0.0, 0.0, 0.0};
  double damping[spring_kind_count] = {0.0, 0.0, 0.0};
};

// Provot's lattice springs on a make_grid() mesh: structural between lattice neighbours,
// shear along both quad diagonals (to the centre vertex for `cross`), bend two lattice steps
// apart. Rest lengths from `rest_positions`.
SpringSet make_lattice_springs(int nx, int ny, GridTriangulation triangulation,
                               const Positions& rest_positions, const SpringStiffness& params);

// Springs on an arbitrary triangle mesh: structural on every edge, bend across every hinge
// (between the two vertices opposite the shared edge); no separate shear springs.
SpringSet make_mesh_springs(const MeshTopology& topology, const Positions& rest_positions,
                            const SpringStiffness& params);

// Sets the stiffness and damping of every spring of one kind (live tuning).
void set_spring_params(SpringSet& springs, SpringKind kind, double stiffness, double damping);

// Elastic energy sum_s k/2 (|xj - xi| - L)^2.
double spring_energy(const SpringSet& springs, const Positions& x);

// Adds elastic and damping spring forces to `force` (3 x n_vertices).
void add_spring_forces(const SpringSet& springs, const Positions& x, const Positions& v, Positions& force);

// Hessian of one spring's energy with respect to its end xj (d = xj - xi, |d| = l):
//   K = k [ d d^T / l^2 + (1 - L/l) (I - d d^T / l^2) ],  and the spring's 6x6 Hessian is
//   [[K, -K], [-K, K]]. With `project_to_psd` the transverse factor (1 - L/l) is clamped at 0,
//   which is exactly the PSD projection of the 6x6 block (its eigenvalues are 2x those of K).
Mat3 spring_hessian_block(const Vec3& d, double rest_length, double stiffness, bool project_to_psd);

// Elastic energy of all springs; adds its gradient and (PSD-projected if asked) Hessian to
// the outputs that are not null. The Hessian uses stencil `stencil` (the springs' vertices).
double evaluate_springs(const SpringSet& springs, const Positions& x, Positions* gradient, SparseHessian* hessian,
                        int stencil, bool project_to_psd);

// The springs' damping as a dissipation potential for implicit Euler, with directions
// lagged at the step start: D(x) = sum gamma/(2h) ((dx_j - dx_i) . u)^2, dx = x - x_start,
// u = unit direction at x_start. Its gradient is minus the damping force at v = dx/h.
double evaluate_spring_damping(const SpringSet& springs, const Positions& x_start, const Positions& x, double h,
                               Positions* gradient, SparseHessian* hessian, int stencil);

}  // namespace weft
