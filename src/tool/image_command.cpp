// spectralize INPUT -o OUTPUT.exr and --to-rgb: the streamed jobs with their console output
// and JSON report.

#include <OpenImageIO/imageio.h>
#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>

#include "colour/colour_space.h"
#include "imagefile/safe_output.h"
#include "pipeline/image_job.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"
#include "tool/console.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

// The report's destination, checked (and its temporary file created) before any work: never
// the input, its config or the output under any alias (the run's registry, imagefile/safe_output.h:
// the output is claimed as soon as its job opens it, and the report is claimed here, first);
// /dev/stdout and /dev/null work as streams.
std::unique_ptr<AtomicOutput> open_report(const Options& opt, const std::string& input) {
  if (opt.report.empty()) return nullptr;
  const std::string inputs[] = {input};
  // The output's place, planned against the report's before either is written.
  FilePlan plan;
  plan.read(input, "the input");
  if (std::string why = plan.write(opt.output, "the output (-o)"); !why.empty())
    throw FileError(why);
  if (std::string why =
          plan.write(opt.report, "the report", WriteRules::named("the report").streams());
      !why.empty())
    throw FileError("--report " + why);
  try {
    return std::make_unique<AtomicOutput>(
        opt.report, WriteRules::named("the report (--report)").streams(), inputs);
  } catch (const FileError& e) {
    throw FileError(std::string("--report ") + e.what());
  }
}

// The report's bytes, into its temporary file (or stream) before the image is committed; the
// caller commits it after the image.
void write_report(AtomicOutput* report, const std::string& json) {
  if (report) report->write(json + "\n");
}

const OptionNames kFlagNames{"--", "-o"};

}  // namespace

int run_to_rgb(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"-o OUTPUT is required"};
  const JobPlan plan = usage_checked("", [&] {
    return plan_to_rgb(opt.settings, opt.output,
                       opt.given.count("--format") || opt.given.count("-d"),
                       opt.given.count("--compression") > 0, kFlagNames);
  });
  const Settings& s = plan.settings;
  auto report = open_report(opt, opt.to_rgb);
  const LogFn log = console_log(opt.verbosity);
  const ToRgbReport r =
      run_to_rgb_job(plan, opt.to_rgb, opt.output, console_progress(opt.verbosity, opt.to_rgb), log,
                     [&](const ToRgbReport& done) {
                       if (report) write_report(report.get(), report_json(done));
                     });
  if (report) report->commit();
  if (opt.verbosity > 0)
    fmt::print(
        stderr, "spectralize: '{}' -> '{}': {}x{}, {} {} bands {}..{} nm{} -> {}{}; {:.2f} s\n",
        r.input, r.output, r.width, r.height, r.bands, r.kind, r.first_nm, r.last_nm,
        r.polarised ? " (polarised: S0 used)" : "", r.colorspace,
        r.kind == "reflective" ? " under " + s.spectral.illuminant : std::string(), r.seconds);
  return kExitOk;
}

int run_image(const Options& opt) {
  // Validate every flag before any work (exit 2 on a mistake).
  if (opt.inputs.size() != 1)
    throw UsageError{opt.inputs.empty()
                         ? "no input image given"
                         : fmt::format("one input image at a time, got {}", opt.inputs.size())};
  if (opt.output.empty()) throw UsageError{"-o OUTPUT.exr is required"};
  const std::string& input = opt.inputs[0];
  const JobPlan plan =
      usage_checked("", [&] { return plan_to_spectral(opt.settings, opt.output, kFlagNames); });
  auto report = open_report(opt, input);
  const LogFn log = console_log(opt.verbosity);
  ImageJobOptions options;
  options.output.what = "the output (-o)";
  options.before_commit = [&](const ImageReport& done) {
    if (report) write_report(report.get(), report_json(done));
  };
  const ImageReport r =
      run_image_job(plan, input, opt.output, console_progress(opt.verbosity, input), log, options);
  if (report) report->commit();
  const PixelCounts& c = r.counts;
  if (opt.verbosity > 0) {
    fmt::print(stderr,
               "spectralize: '{}' -> '{}': {}x{} {} ({}), {} bands {}, {} {}; out of gamut {}, "
               "invalid {}; max relative XYZ error {:.2g}; {:.2f} s\n",
               r.input, r.output, r.width, r.height, to_string(r.settings.spectral.mode),
               r.colorspace, r.bands, r.settings.spectral.grid.to_string(),
               r.settings.half ? "half" : "float", r.settings.compression, r.out_of_gamut_pixels(),
               c.invalid, c.max_error, r.seconds_total);
  }
  if (opt.verbosity >= 2)
    fmt::print(stderr,
               "spectralize: cache: {} nodes computed, {} reused, {} infeasible, {} direct solves, "
               "{} direct hits; seconds: setup {:.3f}, convert {:.3f}, write {:.3f}\n",
               r.cache.nodes_computed, r.cache.nodes_loaded, r.cache.nodes_infeasible,
               r.cache.fallback_solves, r.cache.fallback_hits, r.seconds_setup, r.seconds_convert,
               r.seconds_write);
  return kExitOk;
}

}  // namespace spectralize::tool
