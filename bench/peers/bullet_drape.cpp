// Bullet peer of the drape benchmark (bench/peers/run): a 2 m N x N cloth dropped from y = 1 onto
// a static sphere of radius 0.5 at the origin, 1 simulated second, with Bullet's deformable
// pipeline and its cloth self collision. Settings and the reasons for them:
// bench/peers/README.md.
//   bullet_drape N final.obj [STEPS]      (STEPS of 1/600 s, default 600)
// Times the stepping loop only (not the scene build), prints one line of key=value fields
// starting with `result`, and writes the final cloth as a Y-up OBJ.
// Build: g++ -O2 -std=c++17 bullet_drape.cpp $(pkg-config --cflags --libs bullet)
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// The shared scene (SI units, +Y up).
constexpr double cloth_size = 2.0;
constexpr double cloth_height = 1.0;
constexpr double sphere_radius = 0.5;
constexpr double gravity_y = -9.81;

// Bullet's settings, as documented in the peers README.
struct DrapeSettings {
  int resolution = 64;             // vertices per side
  int steps = 600;                 // fixed steps of time_step
  double time_step = 1.0 / 600.0;  // explicit elastic forces need small steps (k = 100 diverged at N = 128)
  double total_mass = 1.0;         // kg, spread over the nodes
  double spring_stiffness = 40.0;  // N/m, structural, diagonal and bending links
  double spring_damping = 0.05;
  double bending_stiffness = 0.5;
  double margin = 0.005;     // cloth thickness: self contact below 2 x margin
  double friction = 0.5;     // cloth kDF and the sphere's friction
  double sdf_voxel = 0.005;  // sparse-SDF cell for cloth-vs-sphere distances
};

// Final-state figures of the cloth.
struct ClothFigures {
  double min_y = 0.0;
  double max_y = 0.0;
  int inside_1cm = 0;  // nodes more than 1 cm inside the sphere
  int nonfinite = 0;   // nodes with a NaN or infinite coordinate
};

// Owns every Bullet object of the scene; the destructor takes them down in the order Bullet
// needs (bodies out of the world, then the world, then what the world referred to).
class DrapeWorld {
 public:
  explicit DrapeWorld(const DrapeSettings& settings) {
    const btVector3 gravity(0, btScalar(gravity_y), 0);
    collision_config_ = new btSoftBodyRigidBodyCollisionConfiguration();
    dispatcher_ = new btCollisionDispatcher(collision_config_);
    broadphase_ = new btDbvtBroadphase();
    body_solver_ = new btDeformableBodySolver();
    constraint_solver_ = new btDeformableMultiBodyConstraintSolver();
    constraint_solver_->setDeformableSolver(body_solver_);
    world_ = new btDeformableMultiBodyDynamicsWorld(dispatcher_, broadphase_, constraint_solver_,
                                                    collision_config_, body_solver_);
    // Explicit elastic forces with velocity projection, no line search: the world's defaults,
    // spelled out because the implicit mode diverged for every stiffness tried.
    world_->setImplicit(false);
    world_->setUseProjection(true);
    world_->setLineSearch(false);
    world_->setGravity(gravity);
    btSoftBodyWorldInfo& info = world_->getWorldInfo();
    info.m_gravity = gravity;
    info.air_density = 0;
    info.m_sparsesdf.setDefaultVoxelsz(btScalar(settings.sdf_voxel));
    info.m_sparsesdf.Reset();

    // Static sphere (mass 0) at the origin.
    sphere_shape_ = new btSphereShape(btScalar(sphere_radius));
    btTransform origin;
    origin.setIdentity();
    sphere_motion_ = new btDefaultMotionState(origin);
    sphere_ = new btRigidBody(btRigidBody::btRigidBodyConstructionInfo(0, sphere_motion_, sphere_shape_));
    sphere_->setFriction(btScalar(settings.friction));
    world_->addRigidBody(sphere_);

    // Horizontal cloth, quads cut by alternating diagonals, nothing fixed.
    const btScalar half = btScalar(cloth_size / 2), y = btScalar(cloth_height);
    cloth_ = btSoftBodyHelpers::CreatePatch(info, btVector3(-half, y, -half), btVector3(half, y, -half),
                                            btVector3(-half, y, half), btVector3(half, y, half),
                                            settings.resolution, settings.resolution, 0, true);
    cloth_->getCollisionShape()->setMargin(btScalar(settings.margin));
    cloth_->m_cfg.kDF = btScalar(settings.friction);
    cloth_->generateBendingConstraints(2);  // distance-2 links, which the bending force acts on
    cloth_->setTotalMass(btScalar(settings.total_mass));
    // Cloth-vs-rigid through the sparse SDF (nodes, with normal-cone), cloth-vs-cloth faces.
    cloth_->m_cfg.collisions =
        btSoftBody::fCollision::SDF_RD | btSoftBody::fCollision::SDF_RDN | btSoftBody::fCollision::VF_DD;
    world_->addSoftBody(cloth_);
    cloth_->setSelfCollision(true);
    springs_ =
        new btDeformableMassSpringForce(btScalar(settings.spring_stiffness),
                                        btScalar(settings.spring_damping), true, settings.bending_stiffness);
    world_->addForce(cloth_, springs_);
    gravity_ = new btDeformableGravityForce(gravity);
    world_->addForce(cloth_, gravity_);
    cloth_->setActivationState(DISABLE_DEACTIVATION);
  }

  ~DrapeWorld() {
    world_->removeSoftBody(cloth_);
    world_->removeRigidBody(sphere_);
    delete springs_;
    delete gravity_;
    delete cloth_;
    delete sphere_;
    delete sphere_motion_;
    delete sphere_shape_;
    delete world_;
    delete constraint_solver_;
    delete body_solver_;
    delete broadphase_;
    delete dispatcher_;
    delete collision_config_;
  }

  DrapeWorld(const DrapeWorld&) = delete;
  DrapeWorld& operator=(const DrapeWorld&) = delete;

  // One fixed step of h seconds (no substepping, no interpolation).
  void step(double h) { world_->stepSimulation(btScalar(h), 1, btScalar(h)); }

  const btSoftBody& cloth() const { return *cloth_; }

 private:
  btSoftBodyRigidBodyCollisionConfiguration* collision_config_;
  btCollisionDispatcher* dispatcher_;
  btDbvtBroadphase* broadphase_;
  btDeformableBodySolver* body_solver_;
  btDeformableMultiBodyConstraintSolver* constraint_solver_;
  btDeformableMultiBodyDynamicsWorld* world_;
  btSphereShape* sphere_shape_;
  btDefaultMotionState* sphere_motion_;
  btRigidBody* sphere_;
  btSoftBody* cloth_;
  btDeformableMassSpringForce* springs_;
  btDeformableGravityForce* gravity_;
};

ClothFigures measure(const btSoftBody& cloth) {
  ClothFigures figures;
  figures.min_y = INFINITY;
  figures.max_y = -INFINITY;
  for (int i = 0; i < cloth.m_nodes.size(); ++i) {
    const btVector3& x = cloth.m_nodes[i].m_x;
    if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z())) {
      ++figures.nonfinite;
      continue;
    }
    figures.min_y = std::min(figures.min_y, double(x.y()));
    figures.max_y = std::max(figures.max_y, double(x.y()));
    if (x.length() < sphere_radius - 0.01) ++figures.inside_1cm;
  }
  return figures;
}

// Nodes and faces as an OBJ (1-based indices); Bullet's frame is already Y up.
bool write_obj(const std::string& path, const btSoftBody& cloth) {
  FILE* file = std::fopen(path.c_str(), "w");
  if (!file) return false;
  std::fprintf(file, "# bench/peers/bullet_drape final frame, Y up\no cloth\n");
  for (int i = 0; i < cloth.m_nodes.size(); ++i) {
    const btVector3& x = cloth.m_nodes[i].m_x;
    std::fprintf(file, "v %.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  }
  // Faces point at nodes; their index is the offset from the first node.
  const btSoftBody::Node* first = &cloth.m_nodes[0];
  for (int f = 0; f < cloth.m_faces.size(); ++f) {
    const btSoftBody::Face& face = cloth.m_faces[f];
    std::fprintf(file, "f %d %d %d\n", int(face.m_n[0] - first) + 1, int(face.m_n[1] - first) + 1,
                 int(face.m_n[2] - first) + 1);
  }
  return std::fclose(file) == 0;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: %s N final.obj [STEPS]\n", argv[0]);
    return 2;
  }
  DrapeSettings settings;
  settings.resolution = std::atoi(argv[1]);
  if (argc == 4) settings.steps = std::atoi(argv[3]);
  const std::string obj_path = argv[2];
  if (settings.resolution < 2 || settings.steps < 1) {
    std::fprintf(stderr, "bullet_drape: N must be at least 2 and STEPS at least 1\n");
    return 2;
  }

  DrapeWorld drape(settings);

  // Timed: the stepping loop only. The first step also builds Bullet's face tree (lazily),
  // so it is reported apart.
  const auto start = std::chrono::steady_clock::now();
  double first_step_s = 0.0;
  for (int s = 0; s < settings.steps; ++s) {
    drape.step(settings.time_step);
    if (s == 0) first_step_s = seconds_since(start);
  }
  const double wall_s = seconds_since(start);

  const btSoftBody& cloth = drape.cloth();
  const ClothFigures figures = measure(cloth);
  const double simulated_s = settings.steps * settings.time_step;
  std::printf(
      "result simulator=bullet N=%d vertices=%d triangles=%d steps=%d time_step=%.9g simulated_s=%.6g "
      "wall_s=%.6f ms_per_step=%.6f first_step_ms=%.3f min_y=%.6f max_y=%.6f inside_1cm=%d nonfinite=%d\n",
      settings.resolution, cloth.m_nodes.size(), cloth.m_faces.size(), settings.steps, settings.time_step,
      simulated_s, wall_s, 1e3 * wall_s / settings.steps, 1e3 * first_step_s, figures.min_y, figures.max_y,
      figures.inside_1cm, figures.nonfinite);
  std::fflush(stdout);
  if (!write_obj(obj_path, cloth)) {
    std::fprintf(stderr, "bullet_drape: cannot write %s\n", obj_path.c_str());
    return 1;
  }
  return 0;
}
