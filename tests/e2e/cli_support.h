#pragma once
// Helpers for end-to-end tests of the real spectralize binary: run it, capture its output, and
// integrate spectra independently of the library (reading the CIE tables from data/ directly).

#include <sys/wait.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace e2e {

/// A scratch folder named after the running test, removed at the end.
struct Scratch {
  std::filesystem::path dir;
  explicit Scratch(const std::string& prefix = "spectralize") {
    dir = std::filesystem::path(::testing::TempDir()) /
          (prefix + "_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~Scratch() { std::filesystem::remove_all(dir); }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
  /// The names of the files in the folder, sorted (to spot leftovers).
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  /// Writes `text` to a file in the folder and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

struct Run {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Runs `spectralize ARGS` (ARGS already shell-quoted) with an optional environment prefix.
inline Run run(const std::string& args, const std::string& env = "") {
  static int counter = 0;
  std::string base = std::string(::testing::TempDir()) + "spectralize_e2e_" +
                     std::to_string(::getpid()) + "_" + std::to_string(counter++);
  std::string cmd =
      env + " " SPECTRALIZE_BINARY " " + args + " >" + base + ".out 2>" + base + ".err";
  int status = std::system(cmd.c_str());
  Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return r;
}

/// The OpenColorIO the binary uses, from its --version ("... OpenColorIO 2.5.1, ..."), and
/// whether it has OCIO's built-in configs (ocio://..., 2.2 and later).
inline std::string ocio_version() {
  std::smatch m;
  const std::string out = run("--version").out;
  return std::regex_search(out, m, std::regex("OpenColorIO ([0-9.]+)")) ? m[1].str() : "";
}
inline bool ocio_has_builtin_configs() {
  int major = 0, minor = 0;
  std::sscanf(ocio_version().c_str(), "%d.%d", &major, &minor);
  return major > 2 || (major == 2 && minor >= 2);
}

#ifdef SPECTRALIZE_PLUGIN_DIR
/// Runs a stock OIIO tool (with our plugin) and returns its exit code and output (stdout and
/// stderr together, in `out`).
inline Run tool(const std::string& command) {
  const std::string plugins = "OIIO_LIBRARY_PATH=" SPECTRALIZE_PLUGIN_DIR " " SPECTRALIZE_TOOL_ENV;
  const std::string out = ::testing::TempDir() + "tool_" + std::to_string(::getpid());
  const int status = std::system((plugins + " " + command + " >" + out + " 2>&1").c_str());
  Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  std::remove(out.c_str());
  return r;
}
#endif

inline nlohmann::json read_json(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

/// The temporary files of an interrupted run in the folder, named
/// ".<output>.spectralize-XXXXXX.tmp" (the guide's "Files and guarantees" (docs/guide/files.md)).
inline std::vector<std::string> temporaries(const Scratch& s) {
  static const std::regex temporary(R"(^\..*\.spectralize-[A-Za-z0-9]{6}\.tmp$)");
  std::vector<std::string> out;
  for (const auto& name : s.files())
    if (std::regex_match(name, temporary)) out.push_back(name);
  return out;
}

/// Runs a shell command as a child process and returns its exit code (-1 if it did not exit)
/// and its peak resident memory in MB. Cost: the command's.
struct Measured {
  int exit_code = -1;
  double peak_mb = 0;     // peak resident set of the command's largest process
  double seconds = 0;     // wall time
  long minor_faults = 0;  // of the command (and the shell around it)
};
inline Measured run_measured(const std::string& command) {
  Measured m;
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), nullptr);
    _exit(127);
  }
  int status = 0;
  struct rusage usage = {};
  if (wait4(pid, &status, 0, &usage) != pid) return m;
  m.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  m.peak_mb = usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
  m.minor_faults = usage.ru_minflt;
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return m;
}

/// A table of data/*.csv: wavelengths and the named columns, read independently of the library.
struct Table {
  std::vector<double> nm;
  std::vector<std::vector<double>> cols;
};

inline Table read_table(const std::string& file, const std::vector<std::string>& names) {
  std::ifstream f(std::string(SPECTRALIZE_DATA_DIR) + "/" + file);
  std::string line;
  std::getline(f, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::vector<std::size_t> idx;
  for (const auto& n : names)
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == n) idx.push_back(i);
  Table t;
  t.cols.resize(names.size());
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    std::vector<double> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');)
      cells.push_back(cell.empty() ? 0 : std::stod(cell));
    t.nm.push_back(cells[0]);
    for (std::size_t c = 0; c < idx.size(); ++c) t.cols[c].push_back(cells[idx[c]]);
  }
  return t;
}

/// XYZ of the piecewise-linear spectrum (nm, values) on the 1 nm CMF table (trapezoid).
/// Emission (no illuminant): divided by K = sum(tau * ybar) over the whole table. Reflectance
/// (a 1 nm illuminant file on 300..830): divided by the Y of rho == 1 on the same grid, so the
/// reference white has Y = 1 (docs/DESIGN.md §3).
struct Integrated {
  double X, Y, Z;
};

inline Integrated integrate(const std::vector<double>& nm, const std::vector<double>& v,
                            const std::string& cmf_file, const std::string& illuminant_file = "") {
  Table cmf = read_table(cmf_file, {"xbar", "ybar", "zbar"});
  Table ill;
  if (!illuminant_file.empty()) ill = read_table(illuminant_file, {"value"});
  double X = 0, Y = 0, Z = 0, norm = 0;
  for (std::size_t k = 0; k < cmf.nm.size(); ++k) {
    double l = cmf.nm[k];
    double tau = (k == 0 || k + 1 == cmf.nm.size()) ? 0.5 : 1.0;
    double e = 1;
    if (!illuminant_file.empty())
      for (std::size_t j = 0; j < ill.nm.size(); ++j)
        if (ill.nm[j] == l) e = ill.cols[0][j];
    double s = 0;  // linear interpolation of the samples; zero outside the grid
    if (l >= nm.front() && l <= nm.back())
      for (std::size_t i = 0; i + 1 < nm.size(); ++i)
        if (l >= nm[i] && l <= nm[i + 1]) {
          double t = (l - nm[i]) / (nm[i + 1] - nm[i]);
          s = (1 - t) * v[i] + t * v[i + 1];
          break;
        }
    X += tau * e * s * cmf.cols[0][k];
    Y += tau * e * s * cmf.cols[1][k];
    Z += tau * e * s * cmf.cols[2][k];
    bool inside = l >= nm.front() && l <= nm.back();
    norm += tau * e * cmf.cols[1][k] * (illuminant_file.empty() || inside ? 1.0 : 0.0);
  }
  return {X / norm, Y / norm, Z / norm};
}

inline double rel_err(Integrated a, double X, double Y, double Z) {
  double scale = std::max({std::abs(X), std::abs(Y), std::abs(Z)});
  return std::max({std::abs(a.X - X), std::abs(a.Y - Y), std::abs(a.Z - Z)}) / scale;
}

}  // namespace e2e
