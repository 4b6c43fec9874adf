#include "pipeline/render_table.h"

#include <OpenImageIO/parallel.h>
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "classify/input_interpretation.h"
#include "core/colorimetry/renderer_frame.h"
#include "core/tables/table_file.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

Mat3 table_frame(const ColourSpaces& spaces, std::string_view space) {
  std::optional<Mat3> m;
  try {
    m = spaces.facts(space).rgb_to_xyz;
  } catch (const Error&) {
  }
  if (!m || !(relative_error(mul(*m, Xyz{1, 1, 1}), kWhiteD65) <= 1e-3)) return kRec709Frame;
  return *m;
}

Mat3 renderer_matrix(const Settings& s) {
  return RendererMatrix::parse(s.rgb_to_xyz).resolve(Observer::get(s.spectral.observer));
}

double renderer_units(const Spectralizer& sp) {
  const Illuminant* il = sp.illuminant();
  if (!il) return 1.0;  // emission: Y relative to K over 360-830 nm already
  double full = 0;
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k)
    full += ReferenceTable::trapezoid(k) * il->spd[k] * sp.observer().cmf[1][k];
  return full / sp.weights().normalisation();
}

std::array<double, 2> chromaticity_of_column(const Mat3& m, int c) {
  const double sum = m[c] + m[3 + c] + m[6 + c];
  return {m[c] / sum, m[3 + c] / sum};
}

double renderer_primaries_difference(const ColourSpaceFacts& space, const Mat3& renderer) {
  if (!space.primaries_d65) return INFINITY;
  std::array<float, 8> given{};
  for (int c = 0; c < 3; ++c) {
    const auto xy = chromaticity_of_column(renderer, c);
    given[2 * c] = static_cast<float>(xy[0]);
    given[2 * c + 1] = static_cast<float>(xy[1]);
  }
  const Xyz white = mul(renderer, Xyz{1, 1, 1});
  given[6] = static_cast<float>(white.X / white.sum());
  given[7] = static_cast<float>(white.Y / white.sum());
  // The largest difference of the three primaries' x or y (the white left out).
  auto primaries_apart = [](const std::array<float, 8>& a, const std::array<float, 8>& b) {
    double worst = 0;
    for (int k = 0; k < 6; ++k) worst = std::max(worst, std::abs(static_cast<double>(a[k]) - b[k]));
    return worst;
  };
  // The space's own primaries as its standard states them (ACES: AP0, AP1 with the ACES
  // white), the white free: a renderer's white comes from its own illuminant data.
  const double own =
      space.chromaticities ? primaries_apart(given, *space.chromaticities) : INFINITY;
  // Else both adapted to D65 as a config adapts its spaces (Bradford): a space no standard
  // names, given with its own white (DCI-P3 with the DCI white), or as the config sees it.
  const double adapted = primaries_apart(adapt_chromaticities_to_d65(given.data()),
                                         adapt_chromaticities_to_d65(space.primaries_d65->data()));
  return std::min(own, adapted);
}

JobPlan plan_table(Settings settings, const std::string& output, const OptionNames& names) {
  std::string ext = std::filesystem::path(output).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".spztab")
    throw Error(names.output + " '" + clip(output) + "': a table file is named NAME.spztab");
  JobPlan plan = plan_colours(std::move(settings), ColourSubject::table, names);
  const Settings& s = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  const ColourSpaceFacts& facts = *plan.colorspace.facts;
  const std::optional<Mat3>& m = facts.rgb_to_xyz;
  if (!m)
    throw Error(names("colorspace") + " " + quote(s.colorspace) +
                ": not an RGB colour space (data, or no RGB -> XYZ conversion)");
  if (!facts.linear) {
    // The linear space of the config with the same primaries and white, to name it (by its
    // interop ID where the config states them).
    std::string linear = spaces.linear_twin(s.colorspace);
    if (linear == s.colorspace) linear.clear();
    throw Error(names("colorspace") + " " + quote(s.colorspace) +
                ": not linear RGB (its conversion to XYZ is not a 3x3 matrix: a transfer curve "
                "or log encoding); a table is looked up with linear RGB, so renderers decode and "
                "filter textures first" +
                (linear.empty()
                     ? std::string(": give a linear space of this config")
                     : ": use " + quote(linear) + ", the linear space with its primaries"));
  }
  if (!s.rgb_to_xyz.empty()) {
    // A renderer's matrix is for the space the table is named after: the same primaries.
    const Mat3 r = renderer_matrix(s);
    const double worst = renderer_primaries_difference(facts, r);
    if (!(worst <= kPrimariesTolerance)) {
      const auto& own = facts.chromaticities ? *facts.chromaticities : std::array<float, 8>{};
      throw Error(names("rgb_to_xyz") + " '" + clip(s.rgb_to_xyz) +
                  "': its primaries are not those of " + quote(s.colorspace) +
                  fmt::format(" (red {:.4g},{:.4g}, green {:.4g},{:.4g}, blue {:.4g},{:.4g}, "
                              "white {:.4g},{:.4g}; a chromaticity differs by {:.3g}",
                              own[0], own[1], own[2], own[3], own[4], own[5], own[6], own[7],
                              worst) +
                  "); name the space it is for with " + names("colorspace"));
    }
  }
  return plan;
}

double feasible_share(const Spectralizer& sp, const ExactTable& table, int steps) {
  const Mat3& m = table.target_from_rgb();
  std::atomic<std::int64_t> inside{0};
  OIIO::parallel_for_chunked(0, static_cast<int64_t>(steps) * steps, 8, [&](int64_t b, int64_t e) {
    std::int64_t n = 0;
    for (int64_t k = b; k < e; ++k)
      for (int i = 0; i < steps; ++i) {
        const Xyz rgb{(i + 0.5) / steps, (k % steps + 0.5) / steps, (k / steps + 0.5) / steps};
        Outcome outcome = Outcome::exact;
        sp.mapped_target(mul(m, rgb), outcome);
        n += outcome == Outcome::exact;
      }
    inside += n;
  });
  return static_cast<double>(inside) / (static_cast<double>(steps) * steps * steps);
}

RenderTable make_render_table(const JobPlan& plan, const LogFn& log) {
  const auto start = std::chrono::steady_clock::now();
  const Settings& s = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  const std::optional<Mat3>& m = spaces.facts(s.colorspace).rgb_to_xyz;
  if (!m) throw Error("colour space " + quote(s.colorspace) + " has no RGB -> XYZ matrix");
  const Spectralizer sp(s.spectral);
  Mat3 frame = *m;
  if (!s.rgb_to_xyz.empty()) {
    // The spectra reproduce the renderer's XYZ itself: the frame is its matrix with the
    // white balance of the mode (docs/DESIGN.md §3), which ExactTable applies, undone, in the
    // table's units (a reflectance's Y relative to rho == 1 on the grid, a renderer's to the
    // illuminant's Y over 360-830 nm; the same on a 360:830 grid).
    const Xyz balance = sp.target_of(Xyz{1, 1, 1});
    const double units = renderer_units(sp);
    frame = scale_rows(Xyz{units / balance.X, units / balance.Y, units / balance.Z},
                       renderer_matrix(s));
  }
  ExactTable table(sp, frame);
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
  r.feasible = feasible_share(sp, table);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.stats.nodes_constructed > 0)
    log(1, std::to_string(r.stats.nodes_constructed) +
               " node spectra made exact by construction (the model's solve was not exact)");
  return r;
}

}  // namespace spectralize
