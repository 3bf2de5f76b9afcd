#include "report_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace fs = std::filesystem;

bool write_file(const fs::path& path, const std::string& text, std::string& error) {
  // Written beside and renamed over: a run killed while writing leaves the previous file or
  // none, never a truncated one (merge.h reads report.json from other processes' directories).
  fs::path partial = path;
  partial += ".partial";
  {
    std::ofstream file(partial);
    file << text;
    file.flush();
    if (!file) {
      error = "cannot write " + partial.string();
      return false;
    }
  }
  std::error_code renamed;
  fs::rename(partial, path, renamed);
  if (renamed) {
    error = "cannot rename " + partial.string() + " to " + path.string() + ": " + renamed.message();
    return false;
  }
  return true;
}

std::string errors_table(const ErrorCounts& errors) {
  std::string out = "# kind count\n";
  bool any = false;
  for (const auto& [kind, n] : errors) {
    if (n == 0) continue;
    out += kind + ' ' + std::to_string(n) + '\n';
    any = true;
  }
  if (!any) out += "none 0\n";
  return out;
}

std::string distribution_table(std::vector<double> ms, const char* header) {
  std::sort(ms.begin(), ms.end());
  std::string out = std::string(header) + "\n";
  if (ms.empty()) return out + "0 0\n";
  char line[64];
  for (std::size_t i = 0; i < ms.size(); ++i) {
    std::snprintf(line, sizeof line, "%.3f %.6f\n", ms[i],
                  static_cast<double>(i + 1) / static_cast<double>(ms.size()));
    out += line;
  }
  return out;
}

std::string percent_object_json(const std::map<std::string, double>& percent) {
  std::string out = "{";
  for (const auto& [name, value] : percent) {
    if (out.size() > 1) out += ',';
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", std::isfinite(value) ? value : 0.0);
    out += tools::json_string(name);
    out += ':';
    out += text;
  }
  return out + "}";
}

const char* const kGnuplotPreamble =
    "set terminal pngcairo size 960,600 noenhanced font 'sans,10'\n"
    "set grid\nset key top left\nset xlabel 'time since start (s)'\n";

namespace {

/// `text` inside a single-quoted gnuplot string: a quote doubled.
std::string gnuplot_quoted(const char* text) {
  std::string out;
  for (const char* c = text; *c; ++c) {
    out += *c;
    if (*c == '\'') out += '\'';
  }
  return out;
}

}  // namespace

std::string gnuplot_png(const char* file, const char* title, const char* ylabel) {
  return std::string("set output '") + file + "'\nset title '" + gnuplot_quoted(title) +
         "'\nset ylabel '" + gnuplot_quoted(ylabel) + "'\n";
}

std::string run_gnuplot(const fs::path& dir, const std::string& script) {
  std::string error;
  if (!write_file(dir / "plots.gp", script, error)) return error;
  if (dir.string().find('\'') != std::string::npos) return "the out directory's name has a quote";
  const std::string command = "cd '" + dir.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) {
    return "gnuplot failed (status " + std::to_string(status) + "; see " +
           (dir / "gnuplot.log").string() + "; tools/deps.sh installs gnuplot-nox)";
  }
  return {};
}

}  // namespace ricochet::loadtest
