#include "check/intersection_check.hpp"

#include "check/box_tree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

namespace weft {

namespace {

// ---------------------------------------------------------------------------------------------
// Exact arithmetic on floating-point expansions: a value is held as a sum of doubles, which no
// rounding ever touches, and the sign of the sum is the sign of its largest term.

// a + b == sum + error exactly (Knuth's branch-free two-sum; no ordering of |a|, |b| needed).
void two_sum(double a, double b, double& sum, double& error) {
  sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  error = (a - a_virtual) + (b - b_virtual);
}

// a * b == product + error exactly: fma rounds a * b - product once, and that value is exact.
void two_product(double a, double b, double& product, double& error) {
  product = a * b;
  error = std::fma(a, b, -product);
}

// A sum of doubles kept nonoverlapping, in increasing magnitude, without zeros, so the last
// term carries the sign. Capacity for the 24 triple products (4 doubles each) of orient3d.
class Expansion {
 public:
  // Adds b exactly: the running sum absorbs each term from the smallest up, the rounding
  // errors stay behind as the new smaller terms.
  void add(double b) {
    double carry = b;
    int kept = 0;
    for (int i = 0; i < size_; ++i) {
      double sum, error;
      two_sum(carry, terms_[i], sum, error);
      if (error != 0.0) terms_[kept++] = error;
      carry = sum;
    }
    if (carry != 0.0) terms_[kept++] = carry;
    size_ = kept;
  }

  // Adds sign * x * y * z exactly, as the four doubles of (x * y) * z.
  void add_product(int sign, double x, double y, double z) {
    double xy, xy_error;
    two_product(x, y, xy, xy_error);
    double high, high_error, low, low_error;
    two_product(xy, z, high, high_error);
    two_product(xy_error, z, low, low_error);
    add(sign * high);
    add(sign * high_error);
    add(sign * low);
    add(sign * low_error);
  }

  int sign() const { return size_ == 0 ? 0 : (terms_[size_ - 1] > 0.0 ? 1 : -1); }

 private:
  std::array<double, 100> terms_;  // the first size_ are the sum's terms
  int size_ = 0;
};

int sign_of(double value) { return (value > 0.0) - (value < 0.0); }

// Sign of the permutation (-1)^inversions.
template <std::size_t n>
int permutation_sign(const std::array<int, n>& permutation) {
  int inversions = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) inversions += permutation[i] > permutation[j];
  }
  return inversions % 2 == 0 ? 1 : -1;
}

// a - b, when it is exact (always so for a and b within a factor of 2 of each other: Sterbenz's
// lemma, which covers the corners of neighbouring triangles); false when it rounds.
bool exact_difference(double a, double b, double& difference) {
  difference = a - b;
  const double b_virtual = a - difference;
  const double a_virtual = difference + b_virtual;
  return a_virtual == a && b_virtual == b;
}

// Exact orient3d from exact differences: the 3 x 3 determinant's six triple products summed
// exactly, and 0 at once when a column of it is zero (the four points in one axis-aligned plane).
int orient3d_exact_differences(const Vec3& ad, const Vec3& bd, const Vec3& cd) {
  for (int axis = 0; axis < 3; ++axis) {
    if (ad[axis] == 0.0 && bd[axis] == 0.0 && cd[axis] == 0.0) return 0;
  }
  Expansion determinant;
  determinant.add_product(1, ad.x(), bd.y(), cd.z());
  determinant.add_product(-1, ad.x(), bd.z(), cd.y());
  determinant.add_product(1, ad.y(), bd.z(), cd.x());
  determinant.add_product(-1, ad.y(), bd.x(), cd.z());
  determinant.add_product(1, ad.z(), bd.x(), cd.y());
  determinant.add_product(-1, ad.z(), bd.y(), cd.x());
  return determinant.sign();
}

// Exact orient3d: det[a - d; b - d; c - d]. From the differences where they are exact; else it
// equals the 4 x 4 determinant with rows (p, 1) for p = a, b, c, d, whose Leibniz expansion has
// 24 terms, each a product of three coordinates (the column of ones contributes 1), summed
// exactly; no difference of inputs is ever rounded.
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Four points with one coordinate in common lie in an axis-aligned plane (a flat cloth).
  for (int axis = 0; axis < 3; ++axis) {
    if (a[axis] == d[axis] && b[axis] == d[axis] && c[axis] == d[axis]) return 0;
  }
  Vec3 ad, bd, cd;
  bool exact = true;
  for (int axis = 0; axis < 3; ++axis) {
    exact = exact && exact_difference(a[axis], d[axis], ad[axis]) &&
            exact_difference(b[axis], d[axis], bd[axis]) && exact_difference(c[axis], d[axis], cd[axis]);
  }
  if (exact) return orient3d_exact_differences(ad, bd, cd);
  const std::array<const Vec3*, 4> rows = {&a, &b, &c, &d};
  std::array<int, 4> column_of_row = {0, 1, 2, 3};
  Expansion determinant;
  do {
    double factors[3];
    int count = 0;
    for (int row = 0; row < 4; ++row) {
      if (column_of_row[row] < 3) factors[count++] = (*rows[row])[column_of_row[row]];
    }
    determinant.add_product(permutation_sign(column_of_row), factors[0], factors[1], factors[2]);
  } while (std::next_permutation(column_of_row.begin(), column_of_row.end()));
  return determinant.sign();
}

// Exact orient2d the same way: the 3 x 3 determinant with rows (p, 1), 6 products of two.
int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
  // Three points with one coordinate in common lie on an axis-parallel line.
  if ((a.x() == c.x() && b.x() == c.x()) || (a.y() == c.y() && b.y() == c.y())) return 0;
  // From exact differences: (a - c).x (b - c).y - (a - c).y (b - c).x, its two products exact.
  double acx, acy, bcx, bcy;
  if (exact_difference(a.x(), c.x(), acx) && exact_difference(a.y(), c.y(), acy) &&
      exact_difference(b.x(), c.x(), bcx) && exact_difference(b.y(), c.y(), bcy)) {
    Expansion determinant;
    determinant.add_product(1, acx, bcy, 1.0);
    determinant.add_product(-1, acy, bcx, 1.0);
    return determinant.sign();
  }
  const std::array<const Vec2*, 3> rows = {&a, &b, &c};
  std::array<int, 3> column_of_row = {0, 1, 2};
  Expansion determinant;
  do {
    double factors[2];
    int count = 0;
    for (int row = 0; row < 3; ++row) {
      if (column_of_row[row] < 2) factors[count++] = (*rows[row])[column_of_row[row]];
    }
    determinant.add_product(permutation_sign(column_of_row), factors[0], factors[1], 1.0);
  } while (std::next_permutation(column_of_row.begin(), column_of_row.end()));
  return determinant.sign();
}

// Forward error filter: the floating-point determinant is off by at most a few units in the
// last place of its permanent (the same sum with absolute values); 1e-14 is about 90 of them,
// far more than the ~8 roundings on any path. Below 1e-250 products may underflow, so the
// bound is not trusted there.
constexpr double relative_error_bound = 1e-14;
constexpr double smallest_trusted_permanent = 1e-250;

// ---------------------------------------------------------------------------------------------
// Closed segments and triangles, decided by orientation signs only.

// The two coordinates left when axis `drop` is dropped, in cyclic order.
Vec2 project(const Vec3& p, int drop) { return Vec2(p[(drop + 1) % 3], p[(drop + 2) % 3]); }

// An axis whose projection keeps a, b, c non-collinear, or -1 when a, b, c are collinear. The
// axes are tried from the largest component of the rounded normal down, so the first one tried
// is almost always the answer (exact either way: the order only saves exact evaluations).
int non_degenerate_drop_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a).cwiseAbs();
  std::array<int, 3> axes = {0, 1, 2};
  std::sort(axes.begin(), axes.end(), [&](int i, int j) { return normal[i] > normal[j]; });
  for (const int axis : axes) {
    if (orient2d(project(a, axis), project(b, axis), project(c, axis)) != 0) return axis;
  }
  return -1;
}

// For four coplanar points: an axis along which projecting is one-to-one on the plane they
// span, or on their line when they are collinear, so 2D predicates decide 3D questions.
int coplanar_drop_axis(const std::array<Vec3, 4>& points) {
  for (int i = 0; i < 4; ++i) {
    const int axis = non_degenerate_drop_axis(points[(i + 1) % 4], points[(i + 2) % 4], points[(i + 3) % 4]);
    if (axis >= 0) return axis;
  }
  // Collinear: keep a coordinate in which two distinct points differ.
  for (int i = 1; i < 4; ++i) {
    for (int m = 0; m < 3; ++m) {
      if (points[i][m] != points[0][m]) return (m + 1) % 3;
    }
  }
  return 0;
}

// Closed 2D segments [a, b] and [c, d] share a point; any of them may be a single point.
bool segments_intersect_2d(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int abc = orient2d(a, b, c), abd = orient2d(a, b, d);
  const int cda = orient2d(c, d, a), cdb = orient2d(c, d, b);
  if (abc == 0 && abd == 0 && cda == 0 && cdb == 0) {
    // All on one line (or points): the segments meet iff their extents overlap on both axes.
    for (int axis = 0; axis < 2; ++axis) {
      if (std::max(a[axis], b[axis]) < std::min(c[axis], d[axis]) ||
          std::max(c[axis], d[axis]) < std::min(a[axis], b[axis])) {
        return false;
      }
    }
    return true;
  }
  return abc * abd <= 0 && cda * cdb <= 0;
}

// Point x lies in the closed 2D triangle (p, q, r), which is not degenerate.
bool point_in_triangle_2d(const Vec2& x, const Vec2& p, const Vec2& q, const Vec2& r) {
  const int s0 = orient2d(p, q, x), s1 = orient2d(q, r, x), s2 = orient2d(r, p, x);
  const bool some_negative = s0 < 0 || s1 < 0 || s2 < 0;
  const bool some_positive = s0 > 0 || s1 > 0 || s2 > 0;
  return !(some_negative && some_positive);
}

// Closed 3D segments [a, b] and [c, d] share a point.
bool segments_intersect_3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orient3d(a, b, c, d) != 0) return false;
  const int axis = coplanar_drop_axis({a, b, c, d});
  return segments_intersect_2d(project(a, axis), project(b, axis), project(c, axis), project(d, axis));
}

// Closed segment [a, b] and closed triangle (p, q, r) share a point.
bool segment_intersects_triangle(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r) {
  // Both ends strictly on one side of the plane (never so for a degenerate triangle, whose
  // orientations are all 0): the common case, decided first.
  const int side_a = orient3d(p, q, r, a);
  const int side_b = orient3d(p, q, r, b);
  if (side_a * side_b > 0) return false;
  // A degenerate triangle is the union of its sides.
  const int axis = non_degenerate_drop_axis(p, q, r);
  if (axis < 0) {
    return segments_intersect_3d(a, b, p, q) || segments_intersect_3d(a, b, q, r) ||
           segments_intersect_3d(a, b, r, p);
  }

  // In the triangle's plane: an end inside, or the segment crossing a side.
  if (side_a == 0 && side_b == 0) {
    const Vec2 a2 = project(a, axis), b2 = project(b, axis);
    const Vec2 p2 = project(p, axis), q2 = project(q, axis), r2 = project(r, axis);
    return point_in_triangle_2d(a2, p2, q2, r2) || point_in_triangle_2d(b2, p2, q2, r2) ||
           segments_intersect_2d(a2, b2, p2, q2) || segments_intersect_2d(a2, b2, q2, r2) ||
           segments_intersect_2d(a2, b2, r2, p2);
  }

  // Crossing the plane at one point X: the sign of orient3d(a, b, p, q) is the side of line pq
  // that X is on (times one sign common to the three sides), so X is in the closed triangle
  // iff no two of the three signs are opposite.
  const int s0 = orient3d(a, b, p, q), s1 = orient3d(a, b, q, r), s2 = orient3d(a, b, r, p);
  const bool some_negative = s0 < 0 || s1 < 0 || s2 < 0;
  const bool some_positive = s0 > 0 || s1 > 0 || s2 > 0;
  return !(some_negative && some_positive);
}

// Whether one side of `a` has all of `b` strictly beyond it: the line through the side, with
// a's third corner on one side and b's three corners strictly on the other.
bool side_separates(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b) {
  const int inside = orient2d(a[0], a[1], a[2]);
  for (int k = 0; k < 3; ++k) {
    const Vec2& from = a[k];
    const Vec2& to = a[(k + 1) % 3];
    if (orient2d(from, to, b[0]) * inside < 0 && orient2d(from, to, b[1]) * inside < 0 &&
        orient2d(from, to, b[2]) * inside < 0) {
      return true;
    }
  }
  return false;
}

// Two closed, non-degenerate triangles of one plane share a point iff no side of either
// separates them: disjoint compact convex polygons have a separating line through a side of
// one of them (the separating axis theorem), with the other strictly beyond it.
bool coplanar_triangles_intersect(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q) {
  return !side_separates(p, q) && !side_separates(q, p);
}

// All three of q0, q1, q2 strictly on one side of the plane of (p0, p1, p2). Never true for a
// degenerate (p0, p1, p2), whose orientations are all 0.
bool strictly_one_side(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& q0, const Vec3& q1,
                       const Vec3& q2) {
  const int s0 = orient3d(p0, p1, p2, q0);
  if (s0 == 0) return false;
  return orient3d(p0, p1, p2, q1) == s0 && orient3d(p0, p1, p2, q2) == s0;
}

// ---------------------------------------------------------------------------------------------
// Meshes.

void check_meshes(const std::vector<CheckedMesh>& meshes) {
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const std::string name = "find_triangle_intersections: mesh " + std::to_string(m);
    if (meshes[m].positions == nullptr || meshes[m].triangles == nullptr) {
      throw std::invalid_argument(name + " has no positions or no triangles");
    }
    if (!meshes[m].positions->allFinite())
      throw std::invalid_argument(name + " has a coordinate that is not finite");
    const Triangles& triangles = *meshes[m].triangles;
    const int num_vertices = static_cast<int>(meshes[m].positions->cols());
    if ((triangles.array() < 0).any() || (triangles.array() >= num_vertices).any()) {
      throw std::invalid_argument(name + " has a vertex index outside [0, " + std::to_string(num_vertices) +
                                  ")");
    }
  }
}

Vec3 corner(const CheckedMesh& mesh, int triangle, int k) {
  return mesh.positions->col((*mesh.triangles)(k, triangle));
}

// Corner k of triangle t of `mesh` as a vertex index.
int corner_index(const CheckedMesh& mesh, int triangle, int k) { return (*mesh.triangles)(k, triangle); }

// Triangles (v, a, b) and (v, c, d) that share the vertex v and no other meet somewhere other
// than at v iff the side opposite v of one meets the other triangle. Their intersection I is
// convex and holds v; if it holds a point p != v, follow the ray from v through p to where it
// leaves I, at q on the boundary of one triangle, say (v, a, b). If q is on [a, b], done. If q
// is on [v, a] (or [v, b]), the ray runs along that side, and I ends at q because either the
// side ends there (q = a, on [a, b]) or the other triangle does: then q is on [c, d], or on
// [v, c] / [v, d] running the same way, where it ends at c or d, on [c, d].
//
// When the two are coplanar and neither is degenerate (a flat cloth), each coincides near v with
// its corner's cone, so they meet beyond v iff the cones do: iff a side ray of one cone lies in
// the other (the common cone, when not {v}, is bounded by such a ray; both angles are below pi).
bool meet_beyond_shared_vertex(const Vec3& v, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // c and d strictly on one side of the plane of (v, a, b): (v, c, d) meets it at v alone.
  const int side_c = orient3d(v, a, b, c), side_d = orient3d(v, a, b, d);
  if (side_c * side_d > 0) return false;
  if (side_c == 0 && side_d == 0) {
    const int axis = non_degenerate_drop_axis(v, a, b);
    if (axis >= 0) {
      const Vec2 v2 = project(v, axis), c2 = project(c, axis), d2 = project(d, axis);
      Vec2 a2 = project(a, axis), b2 = project(b, axis);
      const int turn_cd = orient2d(v2, c2, d2);
      if (turn_cd != 0) {
        // Both cones counter-clockwise from their first side ray to their second.
        if (orient2d(v2, a2, b2) < 0) std::swap(a2, b2);
        const Vec2 first = turn_cd > 0 ? c2 : d2, second = turn_cd > 0 ? d2 : c2;
        const auto ray_in_cone = [&v2](const Vec2& x, const Vec2& from, const Vec2& to) {
          return orient2d(v2, from, x) >= 0 && orient2d(v2, x, to) >= 0;
        };
        return ray_in_cone(first, a2, b2) || ray_in_cone(second, a2, b2) || ray_in_cone(a2, first, second) ||
               ray_in_cone(b2, first, second);
      }
    }
  }
  return segment_intersects_triangle(a, b, v, c, d) || segment_intersects_triangle(c, d, v, a, b);
}

// Triangles (v, w, a) and (v, w, b) that share the side [v, w] meet beyond it iff they are
// coplanar and a, b lie on the same side of the line vw (they overlap with area); otherwise the
// other's plane cuts each triangle in [v, w] alone. A degenerate triangle (a on the line vw)
// counts when its far corner lies in the other triangle.
bool meet_beyond_shared_edge(const Vec3& v, const Vec3& w, const Vec3& a, const Vec3& b) {
  if (orient3d(v, w, a, b) != 0) return false;
  const int axis = coplanar_drop_axis({v, w, a, b});
  const Vec2 v2 = project(v, axis), w2 = project(w, axis), a2 = project(a, axis), b2 = project(b, axis);
  const int side_a = orient2d(v2, w2, a2), side_b = orient2d(v2, w2, b2);
  if (side_a != 0 && side_b != 0) return side_a == side_b;
  if (side_a == 0 && side_b == 0) return true;  // two segments along vw: counted
  return side_a == 0 ? point_in_triangle_2d(a2, v2, w2, b2) : point_in_triangle_2d(b2, v2, w2, a2);
}

// Whether two triangles intersect by the standard definition (CGAL's self-intersection test):
// triangles of one mesh that share a vertex intersect when they meet anywhere other than at that
// vertex, those that share a side when they meet anywhere other than along that side, and a
// triangle listed twice (all three corners shared) always. Triangles of different meshes share
// nothing.
bool mesh_triangles_intersect(const std::vector<CheckedMesh>& meshes, int mesh_a, int triangle_a, int mesh_b,
                              int triangle_b) {
  const CheckedMesh& a = meshes[mesh_a];
  const CheckedMesh& b = meshes[mesh_b];
  // match_in_b[i]: the corner of b that is corner i of a, or -1. A triangle that repeats a vertex
  // index (a broken mesh) shares nothing by index: it is tested as the closed set it is.
  const auto repeats_a_vertex = [](const CheckedMesh& mesh, int t) {
    const int c0 = corner_index(mesh, t, 0), c1 = corner_index(mesh, t, 1), c2 = corner_index(mesh, t, 2);
    return c0 == c1 || c1 == c2 || c2 == c0;
  };
  std::array<int, 3> match_in_b = {-1, -1, -1};
  int num_shared = 0;
  if (mesh_a == mesh_b && !repeats_a_vertex(a, triangle_a) && !repeats_a_vertex(b, triangle_b)) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (corner_index(a, triangle_a, i) == corner_index(b, triangle_b, j)) {
          match_in_b[i] = j;
          ++num_shared;
        }
      }
    }
  }
  const Vec3 p0 = corner(a, triangle_a, 0), p1 = corner(a, triangle_a, 1), p2 = corner(a, triangle_a, 2);
  if (num_shared == 0)
    return triangles_intersect(p0, p1, p2, corner(b, triangle_b, 0), corner(b, triangle_b, 1),
                               corner(b, triangle_b, 2));
  if (num_shared == 3) return true;

  // Rotate both triangles so that the shared corners come first.
  int first_shared = 0;
  while (match_in_b[first_shared] < 0 || (num_shared == 2 && match_in_b[(first_shared + 2) % 3] >= 0)) {
    ++first_shared;
  }
  const std::array<Vec3, 3> pa = {corner(a, triangle_a, first_shared),
                                  corner(a, triangle_a, (first_shared + 1) % 3),
                                  corner(a, triangle_a, (first_shared + 2) % 3)};
  const int v_in_b = match_in_b[first_shared];
  if (num_shared == 1) {
    return meet_beyond_shared_vertex(pa[0], pa[1], pa[2], corner(b, triangle_b, (v_in_b + 1) % 3),
                                     corner(b, triangle_b, (v_in_b + 2) % 3));
  }
  // Two shared: pa[0], pa[1] are the shared side; b's third corner is the one matched by neither.
  const int w_in_b = match_in_b[(first_shared + 1) % 3];
  const int other_in_b = 3 - v_in_b - w_in_b;
  return meet_beyond_shared_edge(pa[0], pa[1], pa[2], corner(b, triangle_b, other_in_b));
}

TriangleIntersection ordered(int mesh_a, int triangle_a, int mesh_b, int triangle_b) {
  if (std::tie(mesh_b, triangle_b) < std::tie(mesh_a, triangle_a)) {
    std::swap(mesh_a, mesh_b);
    std::swap(triangle_a, triangle_b);
  }
  return {mesh_a, triangle_a, mesh_b, triangle_b};
}

}  // namespace

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Floating-point determinant by rows a - d, b - d, c - d, and its permanent for the bound.
  const double adx = a.x() - d.x(), ady = a.y() - d.y(), adz = a.z() - d.z();
  const double bdx = b.x() - d.x(), bdy = b.y() - d.y(), bdz = b.z() - d.z();
  const double cdx = c.x() - d.x(), cdy = c.y() - d.y(), cdz = c.z() - d.z();
  const double bdx_cdy = bdx * cdy, cdx_bdy = cdx * bdy;
  const double cdx_ady = cdx * ady, adx_cdy = adx * cdy;
  const double adx_bdy = adx * bdy, bdx_ady = bdx * ady;
  const double determinant =
      adz * (bdx_cdy - cdx_bdy) + bdz * (cdx_ady - adx_cdy) + cdz * (adx_bdy - bdx_ady);
  const double permanent = (std::abs(bdx_cdy) + std::abs(cdx_bdy)) * std::abs(adz) +
                           (std::abs(cdx_ady) + std::abs(adx_cdy)) * std::abs(bdz) +
                           (std::abs(adx_bdy) + std::abs(bdx_ady)) * std::abs(cdz);
  if (permanent > smallest_trusted_permanent && std::abs(determinant) > relative_error_bound * permanent) {
    return sign_of(determinant);
  }
  return orient3d_exact(a, b, c, d);
}

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double left = (a.x() - c.x()) * (b.y() - c.y());
  const double right = (a.y() - c.y()) * (b.x() - c.x());
  const double determinant = left - right;
  const double permanent = std::abs(left) + std::abs(right);
  if (permanent > smallest_trusted_permanent && std::abs(determinant) > relative_error_bound * permanent) {
    return sign_of(determinant);
  }
  return orient2d_exact(a, b, c);
}

bool triangles_intersect(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& q0, const Vec3& q1,
                         const Vec3& q2) {
  // Disjoint bounding boxes (exact: min and max do not round).
  const Vec3 p_lower = p0.cwiseMin(p1).cwiseMin(p2), p_upper = p0.cwiseMax(p1).cwiseMax(p2);
  const Vec3 q_lower = q0.cwiseMin(q1).cwiseMin(q2), q_upper = q0.cwiseMax(q1).cwiseMax(q2);
  if ((p_upper.array() < q_lower.array()).any() || (q_upper.array() < p_lower.array()).any()) return false;

  // One triangle strictly on one side of the other's plane.
  if (strictly_one_side(p0, p1, p2, q0, q1, q2) || strictly_one_side(q0, q1, q2, p0, p1, p2)) return false;

  // Coplanar and neither degenerate (a flat cloth): decided in the plane.
  if (orient3d(p0, p1, p2, q0) == 0 && orient3d(p0, p1, p2, q1) == 0 && orient3d(p0, p1, p2, q2) == 0) {
    const int axis = non_degenerate_drop_axis(p0, p1, p2);
    if (axis >= 0) {
      const std::array<Vec2, 3> p2d = {project(p0, axis), project(p1, axis), project(p2, axis)};
      const std::array<Vec2, 3> q2d = {project(q0, axis), project(q1, axis), project(q2, axis)};
      if (orient2d(q2d[0], q2d[1], q2d[2]) != 0) return coplanar_triangles_intersect(p2d, q2d);
    }
  }

  // Two closed triangles meet iff a side of one meets the other: the intersection is convex,
  // and its extreme points lie on the boundary of one of the two.
  return segment_intersects_triangle(p0, p1, q0, q1, q2) || segment_intersects_triangle(p1, p2, q0, q1, q2) ||
         segment_intersects_triangle(p2, p0, q0, q1, q2) || segment_intersects_triangle(q0, q1, p0, p1, p2) ||
         segment_intersects_triangle(q1, q2, p0, p1, p2) || segment_intersects_triangle(q2, q0, p0, p1, p2);
}

bool TriangleIntersection::operator<(const TriangleIntersection& other) const {
  return std::tie(mesh_a, triangle_a, mesh_b, triangle_b) <
         std::tie(other.mesh_a, other.triangle_a, other.mesh_b, other.triangle_b);
}

std::vector<TriangleIntersection> find_triangle_intersections(const std::vector<CheckedMesh>& meshes) {
  check_meshes(meshes);

  // Every triangle's bounding box (exact: min and max do not round); the box tree gives the
  // pairs whose boxes overlap, and only those are tested.
  std::vector<CheckBox> boxes;
  std::vector<std::pair<int, int>> triangle_of_box;  // (mesh, triangle)
  Eigen::Index num_triangles = 0;
  for (const CheckedMesh& mesh : meshes) num_triangles += mesh.triangles->cols();
  boxes.reserve(num_triangles);
  triangle_of_box.reserve(num_triangles);
  for (int m = 0; m < static_cast<int>(meshes.size()); ++m) {
    for (int t = 0; t < static_cast<int>(meshes[m].triangles->cols()); ++t) {
      const Vec3 a = corner(meshes[m], t, 0), b = corner(meshes[m], t, 1), c = corner(meshes[m], t, 2);
      boxes.push_back({a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), meshes[m].obstacle});
      triangle_of_box.emplace_back(m, t);
    }
  }
  // The candidates are tested over the OpenMP threads, each into its own list; the lists are
  // joined and sorted, so the result is the same on any number of threads.
  const std::vector<std::pair<int, int>> candidates = overlapping_box_pairs(boxes);
  const long num_candidates = static_cast<long>(candidates.size());
  std::vector<TriangleIntersection> found;
#pragma omp parallel if (num_candidates > 4096)
  {
    std::vector<TriangleIntersection> mine;
#pragma omp for schedule(dynamic, 512) nowait
    for (long k = 0; k < num_candidates; ++k) {
      const auto [mesh_a, triangle_a] = triangle_of_box[candidates[k].first];
      const auto [mesh_b, triangle_b] = triangle_of_box[candidates[k].second];
      if (mesh_triangles_intersect(meshes, mesh_a, triangle_a, mesh_b, triangle_b)) {
        mine.push_back(ordered(mesh_a, triangle_a, mesh_b, triangle_b));
      }
    }
#pragma omp critical(weft_check_found)
    found.insert(found.end(), mine.begin(), mine.end());
  }
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<TriangleIntersection> find_triangle_intersections(const Positions& positions,
                                                              const Triangles& triangles) {
  return find_triangle_intersections(std::vector<CheckedMesh>{{&positions, &triangles}});
}

std::vector<TriangleIntersection> find_triangle_intersections_brute_force(
    const std::vector<CheckedMesh>& meshes) {
  check_meshes(meshes);
  std::vector<TriangleIntersection> found;
  const int num_meshes = static_cast<int>(meshes.size());
  for (int mesh_a = 0; mesh_a < num_meshes; ++mesh_a) {
    for (int triangle_a = 0; triangle_a < meshes[mesh_a].triangles->cols(); ++triangle_a) {
      for (int mesh_b = mesh_a; mesh_b < num_meshes; ++mesh_b) {
        if (meshes[mesh_a].obstacle && meshes[mesh_b].obstacle) continue;
        const int first_b = mesh_b == mesh_a ? triangle_a + 1 : 0;
        for (int triangle_b = first_b; triangle_b < meshes[mesh_b].triangles->cols(); ++triangle_b) {
          if (mesh_triangles_intersect(meshes, mesh_a, triangle_a, mesh_b, triangle_b)) {
            found.push_back({mesh_a, triangle_a, mesh_b, triangle_b});
          }
        }
      }
    }
  }
  return found;
}

}  // namespace weft
