// spectralize_path_tracer: a small spectral path tracer that takes its spectra from
// spectralize::rt, and what it measures (path_tracer/experiments.h).
//   spectralize_path_tracer convergence --texture PNG --environment EXR --reflectance-table T
//       --emission-table T --texture-spectra EXR --environment-spectra EXR [options]
//   spectralize_path_tracer compare --texture PNG --environment EXR --reflectance-table T
//       [--illuminant A] [--sigmoid-resolution 64] [options]
// Options: --size N, --spp N[,N...], --threads N, --light-scale S, --texture-space NAME,
// --environment-space NAME, --png-prefix PATH, --json FILE.
// Exit status: 0 done, 1 the job failed (the message names the file), 2 a wrong command line.

#include <OpenImageIO/argparse.h>
#include <fmt/core.h>

#include <cmath>
#include <exception>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "imagefile/safe_output.h"
#include "path_tracer/experiments.h"
#include "spectralize/core/error.h"

namespace {

using namespace spectralize;
using namespace spectralize::path_tracer;

constexpr const char* kUsage =
    "usage: spectralize_path_tracer convergence --texture PNG --environment EXR\n"
    "           --reflectance-table FILE --emission-table FILE --texture-spectra EXR\n"
    "           --environment-spectra EXR [options]\n"
    "       spectralize_path_tracer compare --texture PNG --environment EXR\n"
    "           --reflectance-table FILE [--illuminant A] [--sigmoid-resolution 64] [options]\n"
    "           (its table of a model that has not seen the measured chart: not exemplar)\n"
    "options: --size N (64), --spp N[,N...] (4,16,64), --threads N (2), --light-scale S (1),\n"
    "         --texture-space NAME (sRGB - Texture), --environment-space NAME\n"
    "         (Linear Rec.709 (sRGB)), --png-prefix PATH, --json FILE\n";

struct UsageError {
  std::string what;
};

constexpr const char* kFlags[] = {"--texture",
                                  "--texture-space",
                                  "--environment",
                                  "--environment-space",
                                  "--reflectance-table",
                                  "--emission-table",
                                  "--texture-spectra",
                                  "--environment-spectra",
                                  "--light-scale",
                                  "--illuminant",
                                  "--sigmoid-resolution",
                                  "--size",
                                  "--spp",
                                  "--threads",
                                  "--png-prefix",
                                  "--json"};

std::map<std::string, std::string> parse(int argc, const char** argv, std::string& command) {
  std::map<std::string, std::string> given;
  OIIO::ArgParse ap;
  ap.add_help(false).exit_on_error(false);
  std::string extra;  // a second positional argument (reported after parsing)
  ap.arg("command").hidden().action(
      [&](OIIO::cspan<const char*> a) { (command.empty() ? command : extra) = a[0]; });
  for (const char* f : kFlags)
    ap.arg((std::string(f) + " VALUE").c_str())
        .hidden()
        .action([&given, f](OIIO::cspan<const char*> a) { given[f] = a[1]; });
  if (ap.parse_args(argc, argv) < 0) throw UsageError{ap.geterror()};
  if (!extra.empty()) throw UsageError{"unexpected argument '" + extra + "'"};
  return given;
}

int to_int(const std::string& flag, const std::string& v) {
  try {
    std::size_t end = 0;
    const int n = std::stoi(v, &end);
    if (end == v.size() && n >= 1) return n;
  } catch (const std::exception&) {
  }
  throw UsageError{flag + ": expected a whole number >= 1, got '" + v + "'"};
}

RenderSettings render_settings(const std::map<std::string, std::string>& g) {
  RenderSettings r;
  if (g.count("--size")) r.size = to_int("--size", g.at("--size"));
  if (g.count("--threads")) r.threads = to_int("--threads", g.at("--threads"));
  if (g.count("--png-prefix")) r.png_prefix = g.at("--png-prefix");
  if (g.count("--spp")) {
    r.spp.clear();
    const std::string& list = g.at("--spp");
    for (std::size_t a = 0; a <= list.size();) {
      const std::size_t b = std::min(list.find(',', a), list.size());
      r.spp.push_back(to_int("--spp", list.substr(a, b - a)));
      if (r.spp.size() > 1 && r.spp.back() <= r.spp[r.spp.size() - 2])
        throw UsageError{"--spp: counts must increase, got '" + list + "'"};
      a = b + 1;
    }
  }
  return r;
}

float to_float(const std::string& flag, const std::string& v) {
  try {
    std::size_t end = 0;
    const float x = std::stof(v, &end);
    if (end == v.size() && x > 0 && std::isfinite(x)) return x;
  } catch (const std::exception&) {
  }
  throw UsageError{flag + ": expected a number > 0, got '" + v + "'"};
}

std::string required(const std::map<std::string, std::string>& g, const std::string& flag) {
  const auto it = g.find(flag);
  if (it == g.end()) throw UsageError{flag + " is required"};
  return it->second;
}

void write_json(const std::map<std::string, std::string>& g, const std::string& json) {
  const auto it = g.find("--json");
  if (it == g.end()) return;
  AtomicOutput out(it->second, {});
  out.write(json + "\n");
  out.commit();
}

void print(const DeltaEStats& s) {
  fmt::print("mean {:.4g}  p95 {:.4g}  max {:.4g}", s.mean, s.p95, s.max);
}

int run(const std::string& command, const std::map<std::string, std::string>& g) {
  if (command == "convergence") {
    ConvergenceSetup s;
    s.texture = required(g, "--texture");
    s.environment = required(g, "--environment");
    s.reflectance_table = required(g, "--reflectance-table");
    s.emission_table = required(g, "--emission-table");
    s.texture_spectra = required(g, "--texture-spectra");
    s.environment_spectra = required(g, "--environment-spectra");
    if (g.count("--texture-space")) s.texture_space = g.at("--texture-space");
    if (g.count("--environment-space")) s.environment_space = g.at("--environment-space");
    if (g.count("--light-scale")) s.light_scale = to_float("--light-scale", g.at("--light-scale"));
    s.render = render_settings(g);
    const ConvergenceReport r = run_convergence(s);
    for (const ConvergencePoint& p : r.points) {
      fmt::print("rt vs dense reference, {:5d} spp: dE2000 ", p.spp);
      print(p.rt);
      fmt::print("\n");
    }
    fmt::print("floor (rt over all 471 wavelengths vs the reference, {} spp): dE2000 ",
               r.floor_spp);
    print(r.floor);
    fmt::print("  relative XYZ {:.3g}\n", r.floor_relative_xyz);
    fmt::print("{} x {} pixels, {:.2f} s\n", s.render.size, s.render.size, r.seconds);
    write_json(g, to_json(r));
    return 0;
  }
  if (command == "compare") {
    ComparisonSetup s;
    s.texture = required(g, "--texture");
    s.environment = required(g, "--environment");
    s.reflectance_table = required(g, "--reflectance-table");
    if (g.count("--texture-space")) s.texture_space = g.at("--texture-space");
    if (g.count("--environment-space")) s.environment_space = g.at("--environment-space");
    if (g.count("--illuminant")) s.illuminant = g.at("--illuminant");
    if (g.count("--sigmoid-resolution"))
      s.sigmoid_resolution = to_int("--sigmoid-resolution", g.at("--sigmoid-resolution"));
    s.render = render_settings(g);
    const ComparisonReport r = run_comparison(s);
    fmt::print("under {}, {} spp, pixels on surfaces, dE2000 to the measured reflectances:\n",
               r.illuminant, r.spp);
    fmt::print("  spectralize::rt          ");
    print(r.rt_vs_truth);
    fmt::print("\n  Jakob-Hanika {:3d}^3      ", s.sigmoid_resolution);
    print(r.baseline_vs_truth);
    fmt::print("\n  rt vs Jakob-Hanika       ");
    print(r.rt_vs_baseline);
    fmt::print("\n{} x {} pixels, {:.2f} s\n", s.render.size, s.render.size, r.seconds);
    write_json(g, to_json(r));
    return 0;
  }
  throw UsageError{command.empty() ? "expected a command" : "unknown command '" + command + "'"};
}

}  // namespace

int main(int argc, const char** argv) {
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    fmt::print("{}", kUsage);
    return 0;
  }
  try {
    std::string command;
    const auto given = parse(argc, argv, command);
    return run(command, given);
  } catch (const UsageError& e) {
    fmt::print(stderr, "spectralize_path_tracer ERROR: {}\n{}", e.what, kUsage);
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "spectralize_path_tracer ERROR: {}\n", e.what());
    return 1;
  }
}
