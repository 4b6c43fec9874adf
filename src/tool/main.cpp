// spectralize: RGB colours and images to exact spectra (see README.md).

#include <OpenImageIO/argparse.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>

#include "core/error.h"
#include "tool/options.h"

using namespace spectralize;
using namespace spectralize::tool;

namespace {

// Binds "--flag VALUE" to a string field, so every value is validated by the command that uses
// it, with a message naming the flag (ArgParse's own conversions accept garbage as 0).
auto store(std::string& field) {
  return [&field](OIIO::cspan<const char*> args) { field = args[1]; };
}

}  // namespace

int main(int argc, const char** argv) {
  // Past a file-size limit (ulimit -f) a write should fail with EFBIG, reported and cleaned up,
  // not kill the process with SIGXFSZ and leave a partial temporary file behind.
  std::signal(SIGXFSZ, SIG_IGN);
  Options opt;
  OIIO::ArgParse ap;
  ap.intro("spectralize " SPECTRALIZE_VERSION
           " -- exact RGB-to-spectrum conversion (Zhdanov & Potemin)\n"
           "Every spectrum reproduces its input colour exactly, is non-negative, and a reflectance "
           "stays <= 1.")
      .usage(
          "spectralize INPUT -o OUTPUT.exr [options]\n       spectralize --color R,G,B [options]\n"
          "       spectralize --color R,G,B [--color ...] -o PLOT.png|PLOT.svg [options]\n"
          "       spectralize --plot-pixel X,Y IN.exr -o PLOT.png|PLOT.svg")
      .add_help(false)  // ours prints to stdout and exits 0 even with exit_on_error(false)
      .exit_on_error(false);
  bool help = false;
  ap.arg("--help").help("Print this help and exit").action([&](OIIO::cspan<const char*>) {
    help = true;
  });

  ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> args) {
    opt.inputs.emplace_back(args[0]);
  });

  ap.separator("Images (RGB in, spectral OpenEXR out):");
  ap.arg("-o OUTPUT")
      .help(
          "The spectral OpenEXR to write (through a temporary file, renamed when complete); "
          "with --color or --plot-pixel: the plot (.png, .svg, ...)")
      .action(store(opt.output));
  ap.arg("--format FORMAT")
      .help("Samples: half (default) or float; with --color: csv (default) or json")
      .action(store(opt.format));
  ap.arg("--compression NAME")
      .help(
          "OpenEXR compression: zip (default), piz, zips, rle, pxr24, b44, b44a, dwaa, dwab, none")
      .action(store(opt.compression));
  ap.arg("--tile N").help("Write N x N tiles instead of scanlines").action(store(opt.tile));
  ap.arg("--method METHOD")
      .help(
          "table (default: exact interpolation of cached node spectra) or exact (solve every "
          "distinct colour; slow, for comparison)")
      .action(store(opt.method));
  ap.arg("--cache DIR")
      .help("Keep the node table in DIR across runs (keyed by every setting it depends on)")
      .action(store(opt.cache));
  ap.arg("--threads N").help("Threads (default: all cores)").action(store(opt.threads));
  ap.arg("--report FILE")
      .help("Write a JSON report: colour space, counts by kind, errors, cache, timings")
      .action(store(opt.report));
  ap.arg("-v")
      .help("Verbose: stages, colour-space choice, cache statistics")
      .action([&](OIIO::cspan<const char*>) { opt.verbosity = 2; });
  ap.arg("-q")
      .help("Quiet: no progress, summary or warnings")
      .action([&](OIIO::cspan<const char*>) { opt.verbosity = 0; });

  ap.separator("Spectral to RGB:");
  ap.arg("--to-rgb FILE")
      .help(
          "Integrate a spectral OpenEXR (S0 or T channels, any writer) back to RGB(A) in "
          "--colorspace (default Linear Rec.709), reflective files under --illuminant; "
          "write it with -o")
      .action(store(opt.to_rgb));

  ap.separator("Single colours:");
  ap.arg("--color R,G,B")
      .help("Spectralize one colour (repeatable); prints the spectrum to stdout")
      .action([&](OIIO::cspan<const char*> args) { opt.colors.emplace_back(args[1]); });

  ap.separator("Plots (-o PLOT.png, .svg or any image format; 1000x600):");
  ap.arg("--plot-pixel X,Y")
      .help(
          "Plot the spectrum of pixel X,Y (0-based, top-left) of a spectral EXR given as input "
          "(repeatable); with --color R,G,B, -o PLOT.png|.svg draws the colours' spectra instead "
          "of printing them")
      .action([&](OIIO::cspan<const char*> args) { opt.plot_pixels.emplace_back(args[1]); });

  ap.separator("Colour:");
  ap.arg("--colorspace NAME")
      .help(
          "Input colour space, a name or alias of the OCIO config (default: Linear Rec.709 (sRGB))")
      .action(store(opt.colorspace));
  ap.arg("--config FILE")
      .help("OCIO config to use (default: $OCIO, else the config shipped with spectralize)")
      .action(store(opt.config));

  ap.separator("Spectrum:");
  ap.arg("--mode MODE")
      .help(
          "emission (lights, HDR), reflectance (surfaces, rho in [0,1]) or, for images, auto "
          "(default: float data emission, integer data reflectance; --color: emission)")
      .action(store(opt.mode));
  ap.arg("--wavelengths GRID")
      .help("Sampling grid START:END:STEP in nm inside 360..830, step >= 0.5 (default 380:780:5)")
      .action(store(opt.wavelengths));
  ap.arg("--observer NAME")
      .help("CIE standard observer: cie1931 (2 deg, default) or cie1964 (10 deg)")
      .action(store(opt.observer));
  ap.arg("--illuminant NAME")
      .help(
          "Reference illuminant of reflectances: D65 (default), D50, A, C, E, D<nn>, FL1..FL12, "
          "...")
      .action(store(opt.illuminant));
  ap.arg("--filter K")
      .help(
          "Edge-peak filter: drop the K partial solutions with the largest density; a fraction "
          "(0.7), a percentage (70%), a count (1000) or none (default 0.7)")
      .action(store(opt.filter));
  ap.arg("--model NAME")
      .help(
          "How the spectrum is chosen among the exact ones: paper (average of the admissible "
          "partial solutions, default) or smooth (least slope and curvature, within the bounds)")
      .action(store(opt.model));
  ap.arg("--emission-basis NAME")
      .help(
          "Emission only: flat (default) or an illuminant (D65, A, ...): spectrum = E x s with "
          "s >= 0, white balanced to E, so white light becomes E itself")
      .action(store(opt.emission_basis));

  if (ap.parse_args(argc, argv) < 0) {
    std::string err = ap.geterror();
    std::fprintf(stderr, "spectralize ERROR: %s\nRun 'spectralize --help' for the options.\n",
                 err.c_str());
    return kExitUsage;
  }

  if (help) {
    ap.print_help();
    return kExitOk;
  }
  try {
    if (!opt.plot_pixels.empty()) return run_plot_pixel(opt);
    if (int(!opt.colors.empty()) + int(!opt.inputs.empty()) + int(!opt.to_rgb.empty()) > 1)
      throw UsageError{"give one of --color, --to-rgb or an input image"};
    if (!opt.to_rgb.empty()) return run_to_rgb(opt);
    if (!opt.colors.empty()) return run_color(opt);
    if (!opt.inputs.empty() || !opt.output.empty()) return run_image(opt);
    std::fprintf(stderr,
                 "spectralize ERROR: nothing to do: give INPUT -o OUTPUT.exr, or --color R,G,B\n"
                 "Run 'spectralize --help' for the options.\n");
    return kExitUsage;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "spectralize ERROR: %s\n", e.message.c_str());
    return kExitUsage;
  } catch (const Error& e) {
    std::fprintf(stderr, "spectralize ERROR: %s\n", e.what());
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectralize ERROR: %s\n", e.what());
    return kExitFailure;
  }
}
