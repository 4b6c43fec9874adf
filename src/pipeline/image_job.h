#pragma once
// The streamed jobs (docs/DESIGN.md §10): an RGB image (anything OpenImageIO reads: scanline,
// tiled or MIP-mapped) to a spectral OpenEXR, and any spectral OpenEXR back to RGB(A). Rows are
// read, converted and written in strips, so memory is bounded whatever the image size; the
// output goes through an exclusive temporary file that is checked and renamed when complete.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "imagefile/image_reader.h"
#include "imagefile/safe_output.h"
#include "pipeline/image_conversion.h"
#include "pipeline/image_report.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"
#include "pipeline/table_pool.h"
#include "pipeline/thread_share.h"
#include "settings/settings.h"

namespace spectralize {

/// What a caller may add to an image job.
struct ImageJobOptions {
  ConversionContext shared;  // a batch's tables, config and decision; more header attributes
  WriteRules output = WriteRules::named("the output");    // how `output` may be written
  std::function<void(const ImageReport&)> before_commit;  // a throw there leaves nothing
  // The input already open (a batch's decision read its header), read from here instead of
  // opening it again; opened as run_image_job would (spectral_output_channels, straight alpha).
  ImageReader* reader = nullptr;
};

/// Converts `input` to the spectral OpenEXR `output`, as `plan` (plan_to_spectral) says, or as
/// it decided this input already (a batch's planned_input). Never overwrites the input (under any
/// alias) nor another output of the run; nothing is left at `output` unless it completed. The
/// header records the settings as resolved for the file, the conversion's warnings and counts;
/// `before_commit` runs with the finished report before the file is moved into place. Throws
/// Error naming the file and the reason. Cost: O(pixels x bands), plus node solves on first use.
ImageReport run_image_job(const JobPlan& plan, const std::string& input, const std::string& output,
                          const ProgressFn& progress, const LogFn& log,
                          const ImageJobOptions& options = {});

/// Integrates the spectral OpenEXR `input` (any writer's) to RGB(A) as `plan` (plan_to_rgb)
/// says, written to `output` (its format's) like run_image_job. Throws Error.
/// Cost: O(pixels x bands).
ToRgbReport run_to_rgb_job(const JobPlan& plan, const std::string& input, const std::string& output,
                           const ProgressFn& progress, const LogFn& log,
                           const std::function<void(const ToRgbReport&)>& before_commit = {});

}  // namespace spectralize
