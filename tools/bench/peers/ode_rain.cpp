/// The rain benchmark scene (../rain_scene.h) in ODE (double precision): same setup, timing and
/// scoring as physics-bench, for side-by-side comparison.
///
/// One world stepped with dWorldQuickStep (iterations from the command line), ERP 0.2, CFM 1e-5;
/// spheres in a hash space with dCreatePlane floor and walls. Contacts use
/// dContactBounce | dContactApprox1 with mu 0.5, bounce 0.2, bounce_vel 0.1, up to 4 contacts
/// per colliding pair, in a joint group emptied after every step.

#include <ode/ode.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "../rain_scene.h"

namespace {

using ricochet::bench::RainOptions;
using ricochet::bench::RainScene;

constexpr int kMaxContacts = 4;

struct CollideContext {
  dWorldID world;
  dJointGroupID contacts;
  dReal friction;
  dReal restitution;
};

void near_callback(void* data, dGeomID o1, dGeomID o2) {
  const auto* context = static_cast<const CollideContext*>(data);
  dBodyID b1 = dGeomGetBody(o1);
  dBodyID b2 = dGeomGetBody(o2);
  if (b1 == nullptr && b2 == nullptr) return;  // plane against plane
  dContact contact[kMaxContacts];
  const int count = dCollide(o1, o2, kMaxContacts, &contact[0].geom, sizeof(dContact));
  for (int k = 0; k < count; ++k) {
    contact[k].surface.mode = dContactBounce | dContactApprox1;
    contact[k].surface.mu = context->friction;
    contact[k].surface.bounce = context->restitution;
    contact[k].surface.bounce_vel = 0.1;
    dJointID joint = dJointCreateContact(context->world, context->contacts, &contact[k]);
    dJointAttach(joint, b1, b2);
  }
}

int run(const RainOptions& options) {
  const RainScene scene = ricochet::bench::make_rain_scene(options.bodies);
  const int n = scene.bodies;

  dWorldID world = dWorldCreate();
  dWorldSetGravity(world, 0, scene.gravity, 0);
  dWorldSetERP(world, 0.2);
  dWorldSetCFM(world, 1e-5);
  dWorldSetQuickStepNumIterations(world, options.iterations);
  dWorldSetAutoDisableFlag(world, options.sleep != 0 ? 1 : 0);
  dSpaceID space = dHashSpaceCreate(nullptr);
  dJointGroupID contacts = dJointGroupCreate(0);

  // Floor y = 0 and walls x, z = ±wall; ODE planes are a·x + b·y + c·z = d, normal into the arena.
  const double wall = scene.wall;
  dCreatePlane(space, 0, 1, 0, 0);
  dCreatePlane(space, 1, 0, 0, -wall);
  dCreatePlane(space, -1, 0, 0, -wall);
  dCreatePlane(space, 0, 0, 1, -wall);
  dCreatePlane(space, 0, 0, -1, -wall);

  dMass mass;
  dMassSetSphereTotal(&mass, scene.mass, scene.radius);
  std::vector<dBodyID> bodies;
  bodies.reserve(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto p = ricochet::bench::rain_position(scene, i);
    dBodyID body = dBodyCreate(world);
    dBodySetMass(body, &mass);
    dBodySetPosition(body, p[0], p[1], p[2]);
    dGeomID geom = dCreateSphere(space, scene.radius);
    dGeomSetBody(geom, body);
    bodies.push_back(body);
  }

  CollideContext context{world, contacts, scene.friction, scene.restitution};
  const dReal dt = options.dt;
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < options.steps; ++step) {
    dSpaceCollide(space, &context, &near_callback);
    dWorldQuickStep(world, dt);
    dJointGroupEmpty(contacts);
    if (options.progress && ((step + 1) % 60 == 0 || step + 1 == options.steps)) {
      const double elapsed =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      std::fprintf(stderr, "ode: step %d/%d, %.1f ms\n", step + 1, options.steps, elapsed);
    }
  }
  const double total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  std::vector<double> positions(3 * static_cast<size_t>(n));
  std::vector<double> velocities(3 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const dReal* p = dBodyGetPosition(bodies[static_cast<size_t>(i)]);
    const dReal* v = dBodyGetLinearVel(bodies[static_cast<size_t>(i)]);
    for (int k = 0; k < 3; ++k) {
      positions[3 * static_cast<size_t>(i) + static_cast<size_t>(k)] = static_cast<double>(p[k]);
      velocities[3 * static_cast<size_t>(i) + static_cast<size_t>(k)] = static_cast<double>(v[k]);
    }
  }

  dJointGroupDestroy(contacts);
  dSpaceDestroy(space);  // also destroys the geoms (cleanup mode is on by default)
  dWorldDestroy(world);  // also destroys the bodies

  char profile[64];
  std::snprintf(profile, sizeof profile, "{\"total_ms\":%.6g}", total_ms);
  return ricochet::bench::report_rain("ode", options, scene, total_ms, positions, velocities,
                                      profile);
}

}  // namespace

int main(int argc, char** argv) {
  RainOptions options;
  int exit_code = 0;
  if (!ricochet::bench::parse_rain_options(argc, argv, "ode", options, exit_code)) return exit_code;
  dInitODE2(0);
  const int result = run(options);
  dCloseODE();
  return result;
}
