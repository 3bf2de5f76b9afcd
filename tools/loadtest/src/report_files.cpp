#include "report_files.h"

#include <cstdlib>
#include <fstream>

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
