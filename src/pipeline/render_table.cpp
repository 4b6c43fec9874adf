#include "pipeline/render_table.h"

#include <OpenImageIO/parallel.h>

#include <array>
#include <chrono>
#include <filesystem>

#include "classify/input_interpretation.h"
#include "core/table_file.h"
#include "imagefile/safe_output.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

std::optional<Mat3> primaries_matrix(const ColourSpaces& spaces, std::string_view space) {
  if (spaces.is_data(space)) return std::nullopt;
  const ColourTransform t = spaces.to_xyz(space);
  const Mat3 m = from_columns(t(1, 0, 0), t(0, 1, 0), t(0, 0, 1));
  for (double v : m)
    if (!std::isfinite(v)) return std::nullopt;
  if (!(std::abs(det(m)) > 1e-9)) return std::nullopt;
  return m;
}

Mat3 table_frame(const ColourSpaces& spaces, std::string_view space) {
  std::optional<Mat3> m;
  try {
    m = primaries_matrix(spaces, space);
  } catch (const Error&) {
  }
  if (!m || !(relative_error(mul(*m, Xyz{1, 1, 1}), kWhiteD65) <= 1e-3)) return kRec709Frame;
  return *m;
}

bool is_matrix_space(const ColourSpaces& spaces, std::string_view space, const Mat3& m) {
  const ColourTransform t = spaces.to_xyz(space);
  // Inside and outside [0, 1], negative and above 1: a curve, a clamp or an offset shows.
  const Xyz probes[] = {{0.2, 0.5, 0.7}, {0.01, 0.003, 0.02}, {-0.1, 0.4, 0.2}, {1.5, 2.5, 0.3}};
  if (t(0, 0, 0).max_abs() > 1e-7) return false;
  for (const Xyz& c : probes)
    if (!(relative_error(t(c.X, c.Y, c.Z), mul(m, c)) <= 1e-5)) return false;
  return true;
}

JobPlan plan_table(Settings settings, const std::string& output, const OptionNames& names) {
  std::string ext = std::filesystem::path(output).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".spztab")
    throw Error(names.output + " '" + clip(output) + "': a table file is named NAME.spztab");
  JobPlan plan = plan_colours(std::move(settings), ColourSubject::table, names);
  const Settings& s = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  const std::optional<Mat3> m = primaries_matrix(spaces, s.colorspace);
  if (!m)
    throw Error(names("colorspace") + " " + quote(s.colorspace) +
                ": not an RGB colour space (data, or no RGB -> XYZ conversion)");
  if (!is_matrix_space(spaces, s.colorspace, *m)) {
    // The linear space of the config with the same primaries and white, to name it (by its
    // interop ID where the config states them), when it is a matrix space itself.
    std::string linear = spaces.linear_twin(s.colorspace);
    if (!linear.empty() && linear != s.colorspace) {
      const std::optional<Mat3> other = primaries_matrix(spaces, linear);
      if (!other || !is_matrix_space(spaces, linear, *other)) linear.clear();
    } else {
      linear.clear();
    }
    throw Error(names("colorspace") + " " + quote(s.colorspace) +
                ": not linear RGB (its conversion to XYZ is not a 3x3 matrix: a transfer curve "
                "or log encoding); a table is looked up with linear RGB, so renderers decode and "
                "filter textures first" +
                (linear.empty()
                     ? std::string(": give a linear space of this config")
                     : ": use " + quote(linear) + ", the linear space with its primaries"));
  }
  return plan;
}

RenderTable make_render_table(const JobPlan& plan, const LogFn& log) {
  const auto start = std::chrono::steady_clock::now();
  const Settings& s = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  const std::optional<Mat3> m = primaries_matrix(spaces, s.colorspace);
  if (!m) throw Error("colour space " + quote(s.colorspace) + " has no RGB -> XYZ matrix");
  const Spectralizer sp(s.spectral);
  ExactTable table(sp, *m);
  log(1, "table for '" + s.colorspace + "' (" + std::string(to_string(s.spectral.mode)) +
             "): " + table.layout());
  table.build([&](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    OIIO::parallel_for_chunked(
        0, static_cast<int64_t>(n), 64,
        [&](int64_t b, int64_t e) {
          body(static_cast<std::size_t>(b), static_cast<std::size_t>(e));
        },
        OIIO::paropt(s.threads));
  });
  RenderTable r;
  r.colorspace = s.colorspace;
  r.bytes = encode_table_file(table, sp, {s.colorspace, spaces.interop_id(s.colorspace)});
  r.stats = table.stats();
  for (std::size_t n = 0; n < table.node_count(); ++n)
    r.spectra += table.node_spectrum(n) != nullptr;
  r.boundary_cells = r.stats.boundary_cells;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.stats.nodes_constructed > 0)
    log(1, std::to_string(r.stats.nodes_constructed) +
               " node spectra made exact by construction (the model's solve was not exact)");
  return r;
}

void write_render_table(const std::string& path, const RenderTable& table) {
  AtomicOutput out(path, {});
  out.write(table.bytes);
  out.commit();
}

}  // namespace spectralize
