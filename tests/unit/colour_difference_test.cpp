// CIELAB and CIEDE2000 against published values: the 34 test pairs of Sharma, Wu & Dalal,
// "The CIEDE2000 color-difference formula: implementation notes, supplementary test data, and
// mathematical observations", Color Res. Appl. 30 (2005), Table 1 (typed in from the paper; they
// are the independent check), and CIELAB of a few XYZ values worked out by hand from CIE 015;
// CIEDE2000's local metric (the exemplar model's distance) against CIEDE2000 itself at small
// steps.

#include "core/colorimetry/colour_difference.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace spectralize {
namespace {

struct SharmaPair {
  Lab lab1, lab2;
  double de00;
};

// Table 1 of Sharma, Wu & Dalal (2005), pairs 1..34, four decimals as published.
constexpr std::array<SharmaPair, 34> kSharma{{
    {{50.0000, 2.6772, -79.7751}, {50.0000, 0.0000, -82.7485}, 2.0425},
    {{50.0000, 3.1571, -77.2803}, {50.0000, 0.0000, -82.7485}, 2.8615},
    {{50.0000, 2.8361, -74.0200}, {50.0000, 0.0000, -82.7485}, 3.4412},
    {{50.0000, -1.3802, -84.2814}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, -1.1848, -84.8006}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, -0.9009, -85.5211}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, 0.0000, 0.0000}, {50.0000, -1.0000, 2.0000}, 2.3669},
    {{50.0000, -1.0000, 2.0000}, {50.0000, 0.0000, 0.0000}, 2.3669},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0009}, 7.1792},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0010}, 7.1792},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0011}, 7.2195},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0012}, 7.2195},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0009, -2.4900}, 4.8045},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0010, -2.4900}, 4.8045},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0011, -2.4900}, 4.7461},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 0.0000, -2.5000}, 4.3065},
    {{50.0000, 2.5000, 0.0000}, {73.0000, 25.0000, -18.0000}, 27.1492},
    {{50.0000, 2.5000, 0.0000}, {61.0000, -5.0000, 29.0000}, 22.8977},
    {{50.0000, 2.5000, 0.0000}, {56.0000, -27.0000, -3.0000}, 31.9030},
    {{50.0000, 2.5000, 0.0000}, {58.0000, 24.0000, 15.0000}, 19.4535},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.1736, 0.5854}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.2972, 0.0000}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 1.8634, 0.5757}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.2592, 0.3350}, 1.0000},
    {{60.2574, -34.0099, 36.2677}, {60.4626, -34.1751, 39.4387}, 1.2644},
    {{63.0109, -31.0961, -5.8663}, {62.8187, -29.7946, -4.0864}, 1.2630},
    {{61.2901, 3.7196, -5.3901}, {61.4292, 2.2480, -4.9620}, 1.8731},
    {{35.0831, -44.1164, 3.7933}, {35.0232, -40.0716, 1.5901}, 1.8645},
    {{22.7233, 20.0904, -46.6940}, {23.0331, 14.9730, -42.5619}, 2.0373},
    {{36.4612, 47.8580, 18.3852}, {36.2715, 50.5065, 21.2231}, 1.4146},
    {{90.8027, -2.0831, 1.4410}, {91.1528, -1.6435, 0.0447}, 1.4441},
    {{90.9257, -0.5406, -0.9208}, {88.6381, -0.8985, -0.7239}, 1.5381},
    {{6.7747, -0.2908, -2.4247}, {5.8714, -0.0985, -2.2286}, 0.6377},
    {{2.0776, 0.0795, -1.1350}, {0.9033, -0.0636, -0.5514}, 0.9082},
}};

TEST(ColourDifference, MatchesSharmaWuDalalTestData) {
  for (std::size_t i = 0; i < kSharma.size(); ++i) {
    const SharmaPair& p = kSharma[i];
    EXPECT_NEAR(delta_e_2000(p.lab1, p.lab2), p.de00, 1e-4) << "pair " << i + 1;
    // CIEDE2000 is symmetric (the published pairs 7 and 8 are the same pair swapped).
    EXPECT_NEAR(delta_e_2000(p.lab2, p.lab1), p.de00, 1e-4) << "pair " << i + 1 << " swapped";
  }
}

TEST(ColourDifference, EqualColoursHaveZeroDifference) {
  for (const SharmaPair& p : kSharma) {
    EXPECT_EQ(delta_e_2000(p.lab1, p.lab1), 0.0);
  }
  EXPECT_EQ(delta_e_2000({0, 0, 0}, {0, 0, 0}), 0.0);
}

TEST(ColourDifference, LabOfTheWhiteIsL100AndNeutral) {
  const Xyz d65{0.95047, 1.0, 1.08883};
  const Lab w = to_lab(d65, d65);
  EXPECT_NEAR(w.L, 100, 1e-12);
  EXPECT_NEAR(w.a, 0, 1e-12);
  EXPECT_NEAR(w.b, 0, 1e-12);
  // A grey at Y = 0.18 (18% card): L* = 116 * 0.18^(1/3) - 16 = 49.4961 (CIE 015 eq. 8.1).
  const Lab grey = to_lab(0.18 * d65, d65);
  EXPECT_NEAR(grey.L, 116 * std::cbrt(0.18) - 16, 1e-12);
  EXPECT_NEAR(grey.L, 49.4961, 1e-4);
  EXPECT_NEAR(grey.a, 0, 1e-12);
  // Below (6/29)^3 the CIE's linear segment: L* = 903.3 Y (Y = 0.001 -> 0.9033).
  EXPECT_NEAR(to_lab(0.001 * d65, d65).L, 0.9033, 1e-4);
}

TEST(ColourDifference, LabOfSrgbRedUnderD65) {
  // sRGB red (XYZ = first column of the sRGB matrix for the white 0.95047, 1, 1.08883)
  // relative to that white is the familiar L* 53.24, a* 80.09, b* 67.20.
  const Xyz d65{0.95047, 1.0, 1.08883};
  const Lab red = to_lab({0.4124564, 0.2126729, 0.0193339}, d65);
  EXPECT_NEAR(red.L, 53.24, 0.01);
  EXPECT_NEAR(red.a, 80.09, 0.01);
  EXPECT_NEAR(red.b, 67.20, 0.01);
}

TEST(ColourDifference, LocalMetricIsCiede2000AtSmallSteps) {
  // delta_e_2000(at, at + eps d) / eps -> sqrt(d^T Q d) as eps -> 0, for colours of every kind:
  // neutrals (where the hue is undefined), near-neutrals (a* stretch), saturated colours and
  // blues near h = 275 (the rotation term R_T), light and dark (S_L), in random directions.
  // Measured at eps = 1e-5 (the remainder is O(eps)): 1e-3 relative.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Lab> colours = {{50, 0, 0}, {20, 0.3, -0.2}, {90, 0, 0}, {50, 2.5, 0}};
  for (int k = 0; k < 200; ++k) colours.push_back({50 + 45 * u(rng), 80 * u(rng), 80 * u(rng)});
  for (double h = 255; h <= 295; h += 5)  // around CIEDE2000's blue rotation
    colours.push_back({40, 50 * std::cos(h * M_PI / 180), 50 * std::sin(h * M_PI / 180)});
  double worst = 0;
  for (const Lab& at : colours) {
    const LabMetric q = ciede2000_metric(at);
    for (int k = 0; k < 10; ++k) {
      double d[3] = {u(rng), u(rng), u(rng)};
      const double eps = 1e-5;
      const double de = delta_e_2000(at, {at.L + eps * d[0], at.a + eps * d[1], at.b + eps * d[2]});
      const double local = std::sqrt(q.squared(d[0], d[1], d[2]));
      const double rel = std::abs(de / eps - local) / local;
      worst = std::max(worst, rel);
      EXPECT_LE(rel, 1e-3) << "at " << at.L << ", " << at.a << ", " << at.b;
    }
  }
  std::printf("  worst relative difference %.1e\n", worst);
}

TEST(ColourDifference, LocalMetricIsContinuousWhereCiede2000Jumps) {
  // Sharma's pairs 9..12: a hue difference crossing 180 degrees moves CIEDE2000 by 0.04 (the
  // mean hue wraps). The local metric at the first colour of the pair moves by O(the step).
  const Lab at{50, 2.49, -0.001};
  const LabMetric q = ciede2000_metric(at);
  auto dist = [&](const Lab& other) {
    return std::sqrt(q.squared(other.L - at.L, other.a - at.a, other.b - at.b));
  };
  EXPECT_NEAR(delta_e_2000(at, {50, -2.49, 0.0011}) - delta_e_2000(at, {50, -2.49, 0.0009}), 0.0403,
              1e-4);
  EXPECT_LT(std::abs(dist({50, -2.49, 0.0011}) - dist({50, -2.49, 0.0009})), 1e-3);
}

}  // namespace
}  // namespace spectralize
