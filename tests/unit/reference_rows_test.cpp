// The validation's reference lines (figures/reference_rows.h): the nearest-neighbour row leaves
// the patch itself out, starts from the patch nearest in colour and projects it onto the
// patch's colour exactly within 0 <= rho <= 1; rgb2spec fitted per colour reproduces the RGB it
// is given in the space's own primaries. Colours are checked with the test's own reference
// integration (docs/DESIGN.md §3) of measured reflectances of data/. The rgb2spec table row
// (a 64^3 table, seconds to build) is left to the validation's end-to-end run.

#include "figures/reference_rows.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "core/colorimetry/colour_difference.h"
#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize::figures {
namespace {

// XYZ of a reflectance under D65, rho == 1 at Y = 1, by the test's integration.
Xyz under_d65(const std::vector<double>& rho) {
  const SpectralizerSettings defaults;
  const Illuminant d65 = Illuminant::get("D65");
  return test::reference_xyz(defaults.grid, rho, Observer::get(defaults.observer), &d65.spd);
}

Xyz white_d65() {
  return under_d65(std::vector<double>(SpectralizerSettings{}.grid.size(), 1.0));
}

// The D65-referred input colour of a measured reflectance (its XYZ relative to the reflected
// white, scaled to the D65 white: the paper's eq. 6).
Xyz input_of(const std::vector<double>& rho) {
  const Xyz w = white_d65();
  return hadamard(under_d65(rho), {kWhiteD65.X / w.X, kWhiteD65.Y / w.Y, kWhiteD65.Z / w.Z});
}

double delta_e_d65(const std::vector<double>& rho, const Xyz& input) {
  const Xyz w = white_d65();
  const Xyz target = hadamard(input, {w.X / kWhiteD65.X, w.Y / kWhiteD65.Y, w.Z / kWhiteD65.Z});
  return delta_e_2000(to_lab(under_d65(rho), w), to_lab(target, w));
}

struct Context {
  ColourSpaces spaces = ColourSpaces::load();
  ColourTransform to_xyz = spaces.to_xyz("Linear Rec.709 (sRGB)");
  Spectralizer protocol{[] {
    SpectralizerSettings s;
    s.mode = Mode::reflectance;
    return s;
  }()};
  std::vector<std::vector<MeasuredPatch>> measured = load_validation_sets();
  std::vector<std::vector<MeasuredPatch>> sets;
  RowContext row() const { return {"Linear Rec.709 (sRGB)", &to_xyz, &protocol, &sets}; }
  const MeasuredPatch& checker(std::size_t i) const { return measured.at(0).at(i); }
};

TEST(ReferenceRows, AreTheTwoRgb2specLinesThenTheNearestNeighbourNoneAModel) {
  const std::vector<ValidationConfig> rows = reference_rows();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].name, rgb2spec_fit_row().name);
  EXPECT_EQ(rows[1].name, rgb2spec_table_row().name);
  EXPECT_EQ(rows[2].name, nearest_neighbour_row().name);
  // rgb2spec stops at its own Delta E: not exact; the projection is.
  EXPECT_FALSE(rows[0].exact);
  EXPECT_FALSE(rows[1].exact);
  EXPECT_TRUE(rows[2].exact);
  for (const ValidationConfig& r : rows) {
    EXPECT_EQ(r.model, "") << r.name;  // no lights are validated for a reference line
    EXPECT_TRUE(r.make) << r.name;
  }
}

TEST(NearestNeighbour, LeavesThePatchItselfOutAndStartsFromTheNearestOther) {
  Context c;
  const MeasuredPatch& skin = c.checker(1);  // light skin
  const MeasuredPatch& blue = c.checker(12);
  MeasuredPatch copy = skin;
  copy.name = "copy";
  // The same reflectance in another set: it is the patch's nearest neighbour, at distance 0,
  // and projecting it onto its own colour changes nothing.
  c.sets = {{skin, blue}, {copy}};
  {
    const auto row = nearest_neighbour_row().make(c.row());
    const Reconstructed r = row->reconstruct(0, 0, {}, input_of(skin.rho));
    EXPECT_EQ(r.status, "ok");
    EXPECT_LT(test::rel_err(r.values, skin.rho), 1e-6);
  }
  // Alone in the pool but for a blue patch: the blue one, projected onto the skin's colour — a
  // metamer of the skin, far from its measurement.
  c.sets = {{skin, blue}};
  const auto row = nearest_neighbour_row().make(c.row());
  const Reconstructed r = row->reconstruct(0, 0, {}, input_of(skin.rho));
  EXPECT_EQ(r.status, "ok");
  EXPECT_LT(delta_e_d65(r.values, input_of(skin.rho)), 1e-6);
  EXPECT_GT(test::rel_err(r.values, skin.rho), 0.1);
  for (double v : r.values) {
    EXPECT_GE(v, -1e-12);
    EXPECT_LE(v, 1 + 1e-12);
  }
}

TEST(NearestNeighbour, PicksThePatchNearestInColour) {
  Context c;
  const MeasuredPatch& skin = c.checker(1);
  MeasuredPatch darker = skin;  // the same shape, 5% darker: near in colour
  for (double& v : darker.rho) v *= 0.95;
  const std::vector<MeasuredPatch> others = {c.checker(12), c.checker(13), c.checker(3)};
  auto reconstructed = [&](bool with_darker) {
    c.sets = {{skin}};
    for (const MeasuredPatch& p : others) c.sets[0].push_back(p);
    if (with_darker) c.sets[0].insert(c.sets[0].begin() + 2, darker);
    const auto row = nearest_neighbour_row().make(c.row());
    const Reconstructed r = row->reconstruct(0, 0, {}, input_of(skin.rho));
    EXPECT_LT(delta_e_d65(r.values, input_of(skin.rho)), 1e-6);
    return r.values;
  };
  // The darker copy projected back onto the skin's colour is within its 5% of the skin; without
  // it, the nearest of the others is much further.
  const double near = test::rel_err(reconstructed(true), skin.rho);
  const double far = test::rel_err(reconstructed(false), skin.rho);
  EXPECT_LT(near, 0.051);
  EXPECT_GT(far, 2 * near);
}

TEST(Rgb2specFit, ReproducesTheRgbItIsGivenInTheSpacesPrimaries) {
  Context c;
  c.sets = c.measured;
  // A colour given as RGB: the row reads the RGB (the XYZ passed is ignored), in each space's own
  // primaries, and the sigmoid stays strictly inside (0, 1).
  for (const auto& [space, matrix] :
       {std::pair{std::string("Linear Rec.709 (sRGB)"), test::kRec709ToXyz},
        std::pair{std::string("Linear Rec.2020"), test::kRec2020ToXyz}}) {
    SCOPED_TRACE(space);
    const ColourTransform to_xyz = c.spaces.to_xyz(space);
    const auto row = rgb2spec_fit_row().make({space, &to_xyz, &c.protocol, &c.sets});
    for (const std::array<double, 3>& rgb :
         {std::array<double, 3>{0.45, 0.31, 0.22}, std::array<double, 3>{0.1, 0.4, 0.2}}) {
      const Reconstructed r = row->reconstruct(0, 0, rgb, Xyz{});
      EXPECT_EQ(r.status, "ok");
      const Xyz input = test::rgb(matrix, rgb[0], rgb[1], rgb[2]);
      EXPECT_LT(delta_e_d65(r.values, input), 1e-3);
      for (double v : r.values) {
        EXPECT_GT(v, 0);
        EXPECT_LT(v, 1);
      }
    }
  }
}

}  // namespace
}  // namespace spectralize::figures
