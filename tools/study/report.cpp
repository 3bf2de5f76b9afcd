/// report.md: tables, gnuplot scripts and the document around the scenes' sections.

#include "report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "scenes.h"

namespace ricochet::study {

std::string num(double value, int digits) {
  if (!std::isfinite(value)) return value > 0 ? "inf" : value < 0 ? "-inf" : "nan";
  return format("%.*g", digits, value);
}

std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return num(fraction);
  return format("%.3g %%", 100 * fraction);
}

void Report::headline(const std::string& scene, const std::string& text) {
  headlines_.emplace_back(scene, text);
}

void Report::heading(int level, const std::string& text) {
  markdown_ += "\n" + std::string(static_cast<std::size_t>(level), '#') + " " + text + "\n\n";
}

void Report::text(const std::string& paragraph) {
  markdown_ += paragraph + "\n\n";
}

void Report::table(const std::vector<std::string>& header,
                   const std::vector<std::vector<std::string>>& rows) {
  if (rows.empty()) {
    text("*(no rows in this run)*");
    return;
  }
  const auto line = [](const std::vector<std::string>& cells) {
    std::string out = "|";
    for (const std::string& c : cells) out += " " + c + " |";
    return out + "\n";
  };
  markdown_ += line(header);
  markdown_ += "|";
  for (std::size_t i = 0; i < header.size(); ++i) markdown_ += i < 2 ? "---|" : "--:|";
  markdown_ += "\n";
  for (const auto& r : rows) markdown_ += line(r);
  markdown_ += "\n";
}

namespace {

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void Report::plot(const Plot& plot) {
  std::vector<Curve> curves;
  int dropped = 0;
  for (const Curve& c : plot.curves) {
    Curve kept = c;
    kept.points.clear();
    for (const auto& [x, y] : c.points) {
      const bool shown =
          std::isfinite(x) && std::isfinite(y) && (!plot.logx || x > 0) && (!plot.logy || y > 0);
      if (shown) {
        kept.points.emplace_back(x, y);
      } else {
        ++dropped;
      }
    }
    if (!kept.points.empty()) curves.push_back(std::move(kept));
  }
  if (curves.empty()) {
    text("*(plot " + plot.name + ": no data in this run)*");
    return;
  }
  const std::filesystem::path scripts = std::filesystem::path(dir_) / "gnuplot";
  std::error_code ec;
  std::filesystem::create_directories(scripts, ec);
  std::ofstream gp(scripts / (plot.name + ".gp"));
  gp << "set terminal pngcairo size 960,600 noenhanced font 'sans,10'\n";
  gp << "set output " << quoted(plot.name + ".png") << "\n";
  gp << "set title " << quoted(plot.title) << "\n";
  gp << "set xlabel " << quoted(plot.xlabel) << "\n";
  gp << "set ylabel " << quoted(plot.ylabel) << "\n";
  gp << "set grid\nset key outside right top\n";
  if (plot.logx) gp << "set logscale x\nset format x '%g'\n";
  if (plot.logy) gp << "set logscale y\nset format y '%.0e'\n";
  for (const std::string& c : plot.commands) gp << c << "\n";
  for (std::size_t i = 0; i < curves.size(); ++i) {
    gp << "$d" << i << " << EOD\n";
    for (const auto& [x, y] : curves[i].points) gp << format("%.9g %.9g\n", x, y);
    gp << "EOD\n";
  }
  gp << "plot ";
  for (std::size_t i = 0; i < curves.size(); ++i) {
    gp << (i ? ", \\\n     " : "") << "$d" << i << " using 1:2 with " << curves[i].style
       << " title " << quoted(curves[i].title);
  }
  gp << "\n";
  if (!gp) {
    std::fprintf(stderr, "physics-study: cannot write %s\n", (scripts / plot.name).c_str());
    ok_ = false;
  }
  markdown_ += "![" + plot.title + "](" + plot.name + ".png)\n\n";
  if (dropped > 0) {
    text(format("*(%d point%s not drawn: zero, negative or not finite on a log axis.)*", dropped,
                dropped == 1 ? "" : "s"));
  }
}

void Report::knob_table(const std::string& scene, const Setting& base,
                        const std::vector<Knob>& knobs, const std::vector<Column>& columns) {
  const std::vector<std::string> precisions = results_.precisions();
  if (precisions.empty() || columns.empty()) return;
  std::vector<std::string> header = {"knob", "value"};
  for (const Column& c : columns) {
    for (const std::string& p : precisions)
      header.push_back(precisions.size() > 1 ? c.title + " (" + p + ")" : c.title);
  }
  std::vector<std::vector<std::string>> rows;
  for (const Knob knob : knobs) {
    auto sweep = results_.select(scene, precisions[0], columns[0].metric, base, knob);
    if (sweep.size() < 2) continue;
    std::stable_sort(sweep.begin(), sweep.end(), [&](const ResultRow* a, const ResultRow* b) {
      return knob_rank(a->setting, knob) < knob_rank(b->setting, knob);
    });
    for (const ResultRow* r : sweep) {
      const bool is_base = same_except(r->setting, base, 0);
      std::vector<std::string> cells = {knob_name(knob),
                                        knob_value(r->setting, knob) + (is_base ? " (base)" : "")};
      for (const Column& c : columns) {
        for (const std::string& p : precisions) {
          const ResultRow* match = results_.find(scene, p, r->setting, c.metric);
          cells.push_back(match ? c.cell(*match) : "—");
        }
      }
      rows.push_back(std::move(cells));
    }
  }
  table(header, rows);
}

void Report::grid_table(const std::string& scene, const std::string& precision, const Setting& base,
                        Knob row, Knob column, const std::string& metric,
                        const std::function<std::string(const ResultRow&)>& cell) {
  auto sweep = results_.select(scene, precision, metric, base, row | column);
  std::stable_sort(sweep.begin(), sweep.end(), [&](const ResultRow* a, const ResultRow* b) {
    return knob_rank(a->setting, row) < knob_rank(b->setting, row);
  });
  std::vector<std::string> row_values, column_values;
  std::vector<double> column_ranks;
  std::map<std::pair<std::string, std::string>, const ResultRow*> cells;
  for (const ResultRow* r : sweep) {
    const std::string rv = knob_value(r->setting, row), cv = knob_value(r->setting, column);
    if (std::find(row_values.begin(), row_values.end(), rv) == row_values.end())
      row_values.push_back(rv);
    if (std::find(column_values.begin(), column_values.end(), cv) == column_values.end()) {
      // Insert in rank order.
      const double rank = knob_rank(r->setting, column);
      const auto at = std::upper_bound(column_ranks.begin(), column_ranks.end(), rank);
      column_values.insert(column_values.begin() + (at - column_ranks.begin()), cv);
      column_ranks.insert(at, rank);
    }
    cells[{rv, cv}] = r;
  }
  std::vector<std::string> header = {std::string(knob_name(row)) + " \\ " + knob_name(column)};
  header.insert(header.end(), column_values.begin(), column_values.end());
  std::vector<std::vector<std::string>> rows;
  for (const std::string& rv : row_values) {
    std::vector<std::string> cells_of_row = {rv};
    for (const std::string& cv : column_values) {
      const auto it = cells.find({rv, cv});
      cells_of_row.push_back(it == cells.end() ? "—" : cell(*it->second));
    }
    rows.push_back(std::move(cells_of_row));
  }
  table(header, rows);
}

std::vector<Curve> Report::curves(const std::string& scene, const std::string& metric,
                                  const Setting& base, Knob curve, Knob along,
                                  const std::function<double(const ResultRow&)>& x,
                                  const std::function<double(const ResultRow&)>& y) const {
  std::vector<Curve> out;
  const std::vector<std::string> precisions = results_.precisions();
  for (const std::string& p : precisions) {
    const std::size_t first = out.size();
    auto rows = results_.select(scene, p, metric, base, curve | along);
    std::stable_sort(rows.begin(), rows.end(), [&](const ResultRow* a, const ResultRow* b) {
      const double ca = knob_rank(a->setting, curve), cb = knob_rank(b->setting, curve);
      return ca != cb ? ca < cb : knob_rank(a->setting, along) < knob_rank(b->setting, along);
    });
    for (const ResultRow* r : rows) {
      std::string title = knob_value(r->setting, curve);
      if (precisions.size() > 1) title += " " + p;
      auto it = std::find_if(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                             [&](const Curve& c) { return c.title == title; });
      if (it == out.end()) {
        Curve c;
        c.title = title;
        if (p == "double") c.style = "linespoints dashtype 2";
        out.push_back(std::move(c));
        it = out.end() - 1;
      }
      it->points.emplace_back(x(*r), y(*r));
    }
  }
  return out;
}

Curve Report::series_curve(const std::string& scene, const std::string& precision,
                           const std::string& series, const std::string& title,
                           const std::string& style) const {
  Curve c{title, {}, style};
  for (const SeriesPoint& pt : results_.points(scene, precision, series))
    c.points.emplace_back(pt.x, pt.y);
  return c;
}

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown CPU";
}

}  // namespace

bool write_report(const std::string& out_dir, const Results& results, const std::string& mode,
                  const std::string& revision) {
  if (results.precisions().empty()) {
    std::fprintf(stderr, "physics-study: no result rows to report\n");
    return false;
  }
  Report sections(out_dir, results);
  for (const Scene& scene : scenes()) {
    sections.heading(2, std::string(scene.name) + " — " + scene.title);
    scene.report(sections);
  }

  std::string md = "# Physics accuracy ↔ speed study\n\n";
  md += format(
      "Mode **%s**; engine revision `%s`; precisions: %s; measured on %s (%u hardware threads, "
      "shared: timings carry noise of some 10–30 %%).\n\n",
      mode.c_str(), revision.c_str(),
      [&] {
        std::string p;
        for (const std::string& s : results.precisions()) p += (p.empty() ? "" : ", ") + s;
        return p;
      }()
          .c_str(),
      cpu_model().c_str(), std::thread::hardware_concurrency());
  md +=
      "Every number comes from `results.csv` next to this file (one row per scene × setting × "
      "error measure). **Cost** is `ms_per_step`: wall time of `World::step` alone "
      "(`std::chrono::steady_clock`), the median of repeated runs for the short scenes; "
      "`ms_per_sim_s` = ms_per_step / dt is the cost of one simulated second, the fair axis when "
      "dt changes. **energy_drift** is (E_end − E_start)/|E_start| of the total mechanical energy "
      "(kinetic incl. rotation, gravity, spring/attractor potential), signed; scenes that lose "
      "energy by design (restitution < 1, friction) show that loss. **max_penetration** is the "
      "deepest overlap seen during the run, measured from the positions (spheres and planes).\n\n"
      "Each scene has a *base* setting (the engine defaults unless the section says otherwise: "
      "SemiImplicitEuler, dt 1/60, 10 iterations, 1 substep, Baumgarte, continuous collision "
      "off, sleep on). Tables vary one knob at a time around it; the plots add the 2-D sweeps. "
      "Reproduce with `./tools/physics-study --out DIR` (`--quick` for a short run).\n\n";
  md += "## Summary\n\n| scene | headline |\n|---|---|\n";
  for (const auto& [scene, text] : sections.headlines()) md += "| " + scene + " | " + text + " |\n";
  md += "\n" + sections.markdown();

  const std::string path = out_dir + "/report.md";
  std::ofstream out(path);
  out << md;
  if (!out) {
    std::fprintf(stderr, "physics-study: cannot write %s\n", path.c_str());
    return false;
  }
  return sections.ok();
}

}  // namespace ricochet::study
