// spectralize_figures: the paper's figures and the ColorChecker validation.
//   spectralize_figures figures OUTDIR    fig1..fig6 PNGs and difference maps (make figures)
//   spectralize_figures validate OUTDIR   validation.json and .md (make validate)
// Exit status: 0 done, 1 the job failed (the message names the file), 2 a wrong command line.

#include <fmt/core.h>

#include <exception>
#include <iostream>
#include <string>

#include "figures/figures.h"
#include "figures/validation.h"
#include "spectralize/core/error.h"

namespace {

constexpr const char* kUsage =
    "usage: spectralize_figures figures OUTDIR    the paper's figures (PNG) and sphere ΔE\n"
    "       spectralize_figures validate OUTDIR   ColorChecker and illuminant validation\n"
    "                                             (validation.json, validation.md)\n";

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "--help" || command == "-h") {
    fmt::print("{}", kUsage);
    return 0;
  }
  if (argc != 3 || (command != "figures" && command != "validate")) {
    fmt::print(stderr, "spectralize_figures ERROR: expected a command and an output folder\n{}",
               kUsage);
    return 2;
  }
  try {
    if (command == "figures")
      spectralize::figures::make_figures(argv[2], std::cout);
    else
      spectralize::figures::run_validation(argv[2], std::cout);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "spectralize_figures ERROR: {}\n", e.what());
    return 1;
  }
}
