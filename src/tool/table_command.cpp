// spectralize table -o NAME.spztab: the render-time table of a colour space
// (pipeline/render_table.h).

#include <fmt/core.h>

#include <memory>
#include <string>

#include "imagefile/safe_output.h"
#include "pipeline/render_table.h"
#include "settings/settings.h"
#include "spectralize/core/error.h"
#include "text/strings.h"
#include "tool/console.h"
#include "tool/options.h"

namespace spectralize::tool {

int run_table(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"table: -o NAME.spztab is required"};
  if (!opt.inputs.empty())
    throw UsageError{"table takes no input files (got '" + clip(opt.inputs[0]) + "')"};
  JobPlan plan;
  try {
    plan = plan_table(opt.settings, opt.output, OptionNames{"--", "-o"});
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError{e.what()};
  }
  const Settings& s = plan.settings;
  // The destination is checked (and its temporary made) before the work.
  AtomicOutput out(opt.output, {});
  const RenderTable table = make_render_table(plan, console_log(opt.verbosity));
  out.write(table.bytes);
  out.commit();
  if (opt.verbosity > 0)
    fmt::print(stderr,
               "spectralize: wrote '{}': {}, {}, {}, {}; {:.1f} MB, {} node spectra, {} boundary "
               "cells; exact for {:.1f}% of the RGB unit cube (inside the {}; the rest is "
               "mapped); {:.1f} s\n",
               opt.output, table.colorspace, to_string(s.spectral.mode), s.spectral.model.name(),
               s.spectral.grid.to_string(), static_cast<double>(table.bytes.size()) / 1e6,
               table.spectra, table.boundary_cells, 100 * table.feasible,
               s.spectral.mode == Mode::emission ? "spectral locus" : "reflectance solid",
               table.seconds);
  return kExitOk;
}

}  // namespace spectralize::tool
