#pragma once
// One spectral image to one RGB(A) image (docs/DESIGN.md §10): the input's spectral channels as
// the plan decided them, the integration and OCIO conversion (rgb_from_spectral.h), the output's
// spec with its colour tags, and the counts and warnings of what could not be stored. Shared by
// the CLI's streamed job, the OpenImageIO plugin (which serves the same rows on demand) and
// the Python module.

#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <memory>
#include <string>

#include "imagefile/output_formats.h"
#include "pipeline/image_report.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"

namespace spectralize {

class RgbConversion {
 public:
  /// Converts the spectral input `plan` decided (planned_input of a plan_to_rgb plan) of
  /// header `spec`, to be written to `output` as `format` (its compression, and the colour
  /// tags it holds); without a format (a reader: the plugin), the spec is the RGB image's alone.
  /// Warnings go to `log` and the report. Throws Error. Cost: O(bands), an OCIO processor.
  RgbConversion(const JobPlan& plan, const OIIO::ImageSpec& spec, const std::string& output,
                const OutputFormat* format, const LogFn& log);
  ~RgbConversion();

  /// The RGB(A) image's spec (tagged with its colour space or display). Cost: O(1).
  const OIIO::ImageSpec& output_spec() const;
  /// Channels per input pixel (the input's) and per output pixel (3, or 4 with alpha).
  /// Cost: O(1).
  int input_channels() const;
  int output_channels() const;
  /// Converts n input pixels (all input channels, float) to n RGB(A) pixels (float, clamped
  /// to what the output's sample type stores), counting what was not stored as it is, in
  /// parallel on OIIO's pool (settings.threads). Thread-safe. Cost: O(n x bands).
  void convert(const float* in, std::size_t n, float* out);
  /// The report: setup fields; after finish() the counts and their warnings. Cost: O(1).
  const ToRgbReport& report() const { return report_; }
  /// Fills the counts into the report and warns about them. Cost: O(1).
  const ToRgbReport& finish(const LogFn& log);

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
  ToRgbReport report_;
};

}  // namespace spectralize
