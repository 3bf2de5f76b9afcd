/// The scene registry, in report order.

#include "scenes.h"

namespace ricochet::study {

const std::vector<Scene>& scenes() {
  static const std::vector<Scene> all = {
      {"projectile", "Projectile under gravity vs the closed form", run_projectile,
       report_projectile},
      {"spring", "Sphere on a Hooke spring: energy over 60 s", run_spring, report_spring},
      {"orbit", "Sphere orbiting a point attractor: energy over 60 s", run_orbit, report_orbit},
      {"bounce", "Ball dropped from 10 m: apex heights vs h·e^(2k)", run_bounce, report_bounce},
      {"cradle", "Newton's cradle of 3, 5 and 7 spheres and two striking: what reaches the far end",
       run_cradle, report_cradle},
      {"pyramid", "Pyramid of 30 spheres in a corner: drift and jitter", run_pyramid,
       report_pyramid},
      {"column", "Column of 10 spheres in a tube: drift and jitter", run_column, report_column},
      {"slide_to_roll", "Sliding sphere ends rolling at 5/7 v0", run_slide_to_roll,
       report_slide_to_roll},
      {"slope_roll", "Ball rolling down a slope: a = 5/7 g sin(theta)", run_slope_roll,
       report_slope_roll},
      {"rain", "Cost: the rain scene of tools/bench", run_rain, report_rain},
      {"profiles", "Scene profiles: arena_players against the full model", run_profiles,
       report_profiles},
  };
  return all;
}

const Scene* find_scene(const std::string& name) {
  for (const Scene& s : scenes()) {
    if (name == s.name) return &s;
  }
  return nullptr;
}

}  // namespace ricochet::study
