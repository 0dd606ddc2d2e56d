#pragma once
// Contact inside implicit Euler's solve (collision.response "barrier"): the SolveContact of one
// world's meshes. Each cloth's Newton solve sees, as energy, every vertex-face and edge-edge pair
// of the cloth (self, against other cloths, against colliders) closer than the contact radius:
// kappa b(d) with the log barrier b (physics/contact_barrier.hpp) on the pair's distance and
// kappa = stiffness_ratio times the cloth's mean vertex m / h^2, plus lagged Coulomb friction on
// the pairs in contact at the step's start. Its line search never goes past the step that
// additive continuous collision detection (conservative advancement on the pair's distance, after
// Li et al. 2021) allows along the Newton direction, so every iterate keeps each pair's distance
// positive: no impact zones, no CCD passes, no limiter after the solve. The other meshes are
// held where they are during a cloth's solve (cloths solve one after the other); colliders must
// be static (the scene loader refuses moving ones with this response).
//
// The pairs come from the collision hierarchies (collision/primitive_queries.hpp) over boxes
// that hold each cloth vertex's segment along the Newton direction widened by a reuse margin:
// every pair that can come within the contact radius while every vertex stays in its box. The
// list is kept across Newton iterations and steps, and searched again only when a segment
// leaves its vertex's box.
#include <vector>

#include "collision/bvh.hpp"
#include "collision/candidates.hpp"
#include "collision/collider.hpp"
#include "collision/primitive_queries.hpp"
#include "core/topology.hpp"
#include "physics/cloth.hpp"
#include "physics/solve_contact.hpp"

namespace weft {

struct BarrierSettings {
  double contact_radius = 0.0;   // m, dhat; 0: each pair's larger cloth thickness
  double stiffness_ratio = 1.0;  // kappa over the cloth's mean vertex m / h^2
  double slip_speed = 1e-2;      // m/s: friction's smoothing eps is this times h
  // Analytic colliders (plane, sphere, box, capsule, cylinder) by their signed distance, one
  // contact a cloth vertex (fewer pairs than their triangle meshes give), instead of as meshes.
  // Spheres as balls that hold their drawn mesh (BarrierBall: no cloth triangle reaches the
  // mesh); the other shapes by their vertices only, so a cloth triangle may still cut a sharp
  // collider edge or the drawn mesh, which the exact intersection check counts. Off by default.
  bool analytic_colliders = false;
  double min_separation = 0.1;  // a step along a Newton direction keeps each pair at least this
                                // share of its distance at the step's start
  // The candidate boxes' widening around each cloth vertex's segment, over the contact radius:
  // wider boxes list more pairs to evaluate but are left less often.
  double reuse_margin_ratio = 0.5;
};

// A static ball that every cloth triangle keeps out of: a sphere collider as the barrier sees it.
// Its radius R is the sphere's drawn mesh's largest vertex distance from the centre, so the ball
// holds the drawn mesh (the convex hull of those vertices) and a triangle outside the ball is
// outside the mesh: no pair of the exact check can form. The energy is on the cloth's vertices,
// one pair each, their distance from the centre against vertex_radius = sqrt(R^2 + rho^2). At a
// point p = sum_k w_k x_k of a triangle, |p - c|^2 = sum_k w_k |x_k - c|^2 - sum_k w_k |x_k - p|^2,
// and the last sum is at most the squared radius rho_T of the smallest circle holding the
// triangle, so a triangle with rho_T <= rho whose corners are outside vertex_radius is outside
// the ball. A vertex's distance curves as 1 / distance, which Newton's Gauss-Newton contact blocks
// may leave out; a triangle's distance from the centre curves as the centre's distance over the
// triangle's size squared, which they may not (Newton then halves its steps). The triangles' own
// distances still bound every step, for a triangle stretched past rho.
struct BarrierBall {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;         // R, m
  double vertex_radius = 0.0;  // m, at least R
  double friction = 0.0;       // Coulomb coefficient
};

// One mesh as the barrier sees it: a cloth or a static collider surface.
struct BarrierMesh {
  Triangles triangles;     // (3 x n_triangles), local indices
  Positions positions;     // (3 x n_vertices): colliders' fixed pose; cloths' filled each solve
  double thickness = 0.0;  // cloths; 0 for colliders
  double friction = 0.0;   // Coulomb coefficient (a cloth-cloth pair takes the mean)
  bool self_collision = false;
  bool is_cloth = true;
};

class BarrierContact : public SolveContact {
 public:
  BarrierSettings settings;

  // Registers the meshes, cloths first (their positions are read in prepare_cloth), the
  // colliders of analytic shape (plane, box, capsule, cylinder), whose contact is each cloth
  // vertex against the collider's signed distance (collision/collider.hpp), and the balls (each
  // also a sphere of its vertex radius among those); mesh colliders come as meshes. Allocates.
  void set_meshes(const std::vector<BarrierMesh>& meshes, const std::vector<Collider>& analytic = {},
                  const std::vector<BarrierBall>& balls = {});
  int num_meshes() const { return static_cast<int>(slots_.size()); }
  // Before cloth `cloth`'s solve: every cloth's current positions (the others stay there during
  // it) and their positions at the step's start (the others' friction displacement), and the
  // cloth's mean vertex mass. Allocates nothing once grown.
  void prepare_cloth(int cloth, const std::vector<const Positions*>& current,
                     const std::vector<const Positions*>& step_start, const Eigen::VectorXd& inverse_mass,
                     double mean_mass);

  double begin_step(const Positions& x_start, const Positions& predictor, double h) override;
  double max_step(const Positions& x, const Eigen::Ref<const Positions>& dx) override;
  double evaluate(const Positions& x, Positions* gradient, ContactBlocks* blocks) override;
  double evaluate_moving(const Positions& x, const std::vector<char>& moving, Positions* gradient,
                         ContactBlocks* blocks) override;
  double last_potential() const override { return last_potential_; }
  const SolveContactReport& report() const override { return report_; }

 private:
  struct Slot {
    BarrierMesh mesh;
    MeshTopology topology;
    MeshIndexOffsets offsets;
    Triangles global_triangles, vertex_entries, edge_entries;
    Bvh bvh, vertex_bvh, edge_bvh;
    bool built = false;
  };
  // A pair's four vertices in combined indices (vertex-face: the vertex then the triangle's
  // corners; edge-edge: edge a's ends then edge b's), and the two meshes it joins.
  struct Stencil {
    std::array<int, 4> vertices;
    bool edge_edge;
  };
  // A pair's distance at a point: d, the unit normal n from the second primitive to the first,
  // and the weights w with d = n . sum_k w_k x_k.
  struct PairGeometry {
    double distance;
    Vec3 normal;
    std::array<double, 4> weights;
  };
  // A cloth vertex near an analytic collider: its signed distance and outward normal.
  struct SolidPair {
    int vertex;    // local in the solving cloth
    int collider;  // index into analytic_
  };
  // The pairs one search found for a cloth, and the vertex boxes (combined) it covered: they
  // stay the cloth's pairs while every cloth vertex stays in its box (colliders are static).
  struct CandidateCache {
    std::vector<Stencil> stencils;  // with a free vertex of the cloth
    Positions lower, upper;
    bool valid = false;
  };
  struct FrictionPair {
    std::array<int, 4> vertices;  // local cloth vertex, or -1
    std::array<double, 4> weights;
    Mat3 tangent;        // I - n n^T at the step's start
    Vec3 fixed_slip;     // the tangential displacement of the contact's vertices outside the cloth
    double coefficient;  // mu lambda, N
  };

  PrimitiveMesh primitive_mesh(const Slot& slot) const;
  void update_hierarchies(Slot& slot, const Positions& from, const Positions& to);
  Stencil stencil(const VertexFacePair& pair) const;
  Stencil stencil(const EdgeEdgePair& pair) const;
  Vec3 position(int combined, const Positions& x) const;  // the solving cloth's from x
  PairGeometry geometry(const Stencil& stencil, const Positions& x) const;
  double pair_radius(const Stencil& stencil) const;
  double pair_friction(const Stencil& stencil) const;
  bool has_free_vertex(const Stencil& stencil) const;
  bool covered() const;  // the solving cloth's cache holds the segment from_ -> to_
  void search();         // fills the solving cloth's cache around the segment from_ -> to_
  struct PairAdvance {
    double alpha;  // the segment's share the pair allows
    bool near;     // may come within the contact radius along the segment
  };
  PairAdvance advance(const Stencil& stencil) const;
  double advance(const SolidPair& pair, const Positions& x, const Eigen::Ref<const Positions>& dx) const;
  // The share of x -> x + dx along which every cloth triangle keeps out of every ball.
  double advance_balls(const Positions& x, const Eigen::Ref<const Positions>& dx);
  double contact_radius() const;  // the largest pair radius
  struct ContactSums {
    double barrier = 0.0;  // the barrier's energy, friction left out
    int pairs = 0;         // pairs within their radius
  };
  // evaluate() over the contacts with a cloth vertex where `moving` is nonzero (every contact
  // when null); the energy (infinite, with sums left unset, where a pair touches).
  double evaluate_contacts(const Positions& x, const std::vector<char>* moving, Positions* gradient,
                           ContactBlocks* blocks, ContactSums& sums);
  // Whether a contact has a solving-cloth vertex marked in `moving`.
  bool touches(const Stencil& stencil, const std::vector<char>& moving) const;
  static bool touches(const FrictionPair& pair, const std::vector<char>& moving);
  int local(int combined) const;  // local index in the solving cloth, or -1

  std::vector<Slot> slots_;
  std::vector<Collider> analytic_;
  std::vector<SolidPair> solid_pairs_;  // max_step's vertex-collider pairs
  std::vector<double> solid_distance_;  // evaluate()'s scratch, per solid pair
  std::vector<Vec3> solid_normal_;
  std::vector<BarrierBall> balls_;
  std::vector<int> ball_colliders_;             // each ball's vertex collider in analytic_
  const Triangles* cloth_triangles_ = nullptr;  // the solving cloth's
  int num_cloths_ = 0;
  int cloth_ = -1;                // the solving cloth
  Eigen::VectorXd inverse_mass_;  // the solving cloth's
  double mean_mass_ = 0.0;
  double kappa_ = 0.0;            // N/m
  double epsilon_ = 0.0;          // m, friction smoothing
  std::vector<int> vertex_mesh_;  // combined vertex -> mesh
  Eigen::Matrix2Xi edges_;        // combined edges (2 x n_edges)
  Positions from_, to_, start_;   // combined positions: segment ends, step start (3 x n_vertices)
  BvhQueryBuffers buffers_;
  CollisionCandidates candidates_;
  std::vector<CandidateCache> caches_;              // per cloth
  const std::vector<Stencil>* stencils_ = nullptr;  // the solving cloth's cache's
  std::vector<char> near_;                          // max_step's scratch, per stencil
  std::vector<Stencil> active_;         // the stencils that may come within the radius on the last segment
  std::vector<PairGeometry> geometry_;  // scratch of evaluate()
  std::vector<int> selected_;           // evaluate()'s stencils (indices into active_) and solid pairs
  std::vector<int> selected_solids_;
  std::vector<FrictionPair> friction_;
  Positions x_step_start_;  // the solving cloth's positions at the step's start
  double last_potential_ = 0.0;
  SolveContactReport report_;
};

}  // namespace weft
