/// The rain benchmark scene (../rain_scene.h) in Bullet: same setup, timing and scoring as
/// physics-bench, for side-by-side comparison.
///
/// One btDiscreteDynamicsWorld with a dbvt broadphase and the sequential-impulse solver; one
/// shared btSphereShape; floor and walls are btStaticPlaneShape bodies. Every body and plane gets
/// restitution 0.2 and friction 0.5 (Bullet combines them per contact with its default rule, the
/// product). stepSimulation(dt, 0) runs exactly one fixed step of dt per call, no substepping.

#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "../rain_scene.h"

namespace {

using ricochet::bench::RainOptions;
using ricochet::bench::RainScene;

int run(const RainOptions& options) {
  const RainScene scene = ricochet::bench::make_rain_scene(options.bodies);
  const int n = scene.bodies;

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, static_cast<btScalar>(scene.gravity), 0));
  world.getSolverInfo().m_numIterations = options.iterations;

  const auto restitution = static_cast<btScalar>(scene.restitution);
  const auto friction = static_cast<btScalar>(scene.friction);

  // Floor y = 0 and walls x, z = ±wall; each plane is n·p = c with n pointing into the arena.
  const auto wall = static_cast<btScalar>(scene.wall);
  const btVector3 plane_normals[5] = {btVector3(0, 1, 0), btVector3(1, 0, 0), btVector3(-1, 0, 0),
                                      btVector3(0, 0, 1), btVector3(0, 0, -1)};
  const btScalar plane_constants[5] = {0, -wall, -wall, -wall, -wall};
  std::vector<std::unique_ptr<btStaticPlaneShape>> plane_shapes;
  std::vector<std::unique_ptr<btRigidBody>> planes;
  for (int k = 0; k < 5; ++k) {
    plane_shapes.push_back(
        std::make_unique<btStaticPlaneShape>(plane_normals[k], plane_constants[k]));
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, plane_shapes.back().get());
    info.m_restitution = restitution;
    info.m_friction = friction;
    planes.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(planes.back().get());
  }

  btSphereShape sphere(static_cast<btScalar>(scene.radius));
  const auto mass = static_cast<btScalar>(scene.mass);
  btVector3 inertia(0, 0, 0);
  sphere.calculateLocalInertia(mass, inertia);
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  bodies.reserve(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto p = ricochet::bench::rain_position(scene, i);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, &sphere, inertia);
    info.m_startWorldTransform.setIdentity();
    info.m_startWorldTransform.setOrigin(btVector3(
        static_cast<btScalar>(p[0]), static_cast<btScalar>(p[1]), static_cast<btScalar>(p[2])));
    info.m_restitution = restitution;
    info.m_friction = friction;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    if (options.sleep == 0) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
  }

  const auto dt = static_cast<btScalar>(options.dt);
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < options.steps; ++step) {
    world.stepSimulation(dt, 0);
    if (options.progress && ((step + 1) % 60 == 0 || step + 1 == options.steps)) {
      const double elapsed =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      std::fprintf(stderr, "bullet: step %d/%d, %.1f ms\n", step + 1, options.steps, elapsed);
    }
  }
  const double total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  std::vector<double> positions(3 * static_cast<size_t>(n));
  std::vector<double> velocities(3 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const btVector3& p = bodies[static_cast<size_t>(i)]->getWorldTransform().getOrigin();
    const btVector3& v = bodies[static_cast<size_t>(i)]->getLinearVelocity();
    for (int k = 0; k < 3; ++k) {
      positions[3 * static_cast<size_t>(i) + static_cast<size_t>(k)] = static_cast<double>(p[k]);
      velocities[3 * static_cast<size_t>(i) + static_cast<size_t>(k)] = static_cast<double>(v[k]);
    }
  }

  for (auto& body : bodies) world.removeRigidBody(body.get());
  for (auto& plane : planes) world.removeRigidBody(plane.get());

  char profile[64];
  std::snprintf(profile, sizeof profile, "{\"total_ms\":%.6g}", total_ms);
  return ricochet::bench::report_rain("bullet", options, scene, total_ms, positions, velocities,
                                      profile);
}

}  // namespace

int main(int argc, char** argv) {
  RainOptions options;
  int exit_code = 0;
  if (!ricochet::bench::parse_rain_options(argc, argv, "bullet", options, exit_code))
    return exit_code;
  return run(options);
}
