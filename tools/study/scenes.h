#pragma once
/// The scene registry. Each scene runs its sweeps into a Study and writes its section of the
/// report (reading guide, tables, plots) from merged results. Scenes live one or two to a file.

#include <string>
#include <vector>

#include "report.h"
#include "study.h"

namespace ricochet::study {

struct Scene {
  const char* name;  ///< the `scene` column of results.csv
  const char* title;
  void (*run)(Study&);
  void (*report)(Report&);
};

/// Every scene, in report order.
const std::vector<Scene>& scenes();
const Scene* find_scene(const std::string& name);

void run_projectile(Study&);
void report_projectile(Report&);
void run_spring(Study&);
void report_spring(Report&);
void run_orbit(Study&);
void report_orbit(Report&);
void run_bounce(Study&);
void report_bounce(Report&);
void run_cradle(Study&);
void report_cradle(Report&);
void run_pyramid(Study&);
void report_pyramid(Report&);
void run_column(Study&);
void report_column(Report&);
void run_slide_to_roll(Study&);
void report_slide_to_roll(Report&);
void run_slope_roll(Study&);
void report_slope_roll(Report&);
void run_rain(Study&);
void report_rain(Report&);
void run_profiles(Study&);
void report_profiles(Report&);

}  // namespace ricochet::study
