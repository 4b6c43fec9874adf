// Observers, illuminants and the embedded CSV tables (include/spectralize/core/colorimetry.h):
// the CIE data the library embeds, on the 1 nm reference table of docs/DESIGN.md §3. Oracles:
// the CSV files of data/ read and interpolated here, published CIE values, the daylight locus,
// and the test's own trapezoid integration (test_support.h).

#include "spectralize/core/colorimetry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/colorimetry/embedded_data.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::chromaticity;
using test::expect_error_mentioning;
using test::illuminant_xyz;

// Index of wavelength `nm` on the 1 nm reference table.
std::size_t at(int nm) {
  return static_cast<std::size_t>(nm - 360);
}

// A CSV file of data/, read here: the header's cells and the rows' numbers (strtod; an empty
// cell is 0).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};
Csv read_csv(const std::string& name) {
  std::ifstream in(std::string(SPECTRALIZE_DATA_DIR) + "/" + name);
  EXPECT_TRUE(in) << name;
  Csv csv;
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (line.back() == ',') cells.emplace_back();
    if (csv.header.empty()) {
      csv.header = cells;
      continue;
    }
    std::vector<double> row;
    for (const std::string& c : cells)
      row.push_back(c.empty() ? 0.0 : std::strtod(c.c_str(), nullptr));
    csv.rows.push_back(row);
  }
  return csv;
}

// Column `col` of a CSV at `nm` by linear interpolation, the end values held outside.
double csv_at(const Csv& csv, std::size_t col, double nm) {
  const auto& r = csv.rows;
  if (nm <= r.front()[0]) return r.front()[col];
  if (nm >= r.back()[0]) return r.back()[col];
  std::size_t i = 1;
  while (r[i][0] < nm) ++i;
  const double t = (nm - r[i - 1][0]) / (r[i][0] - r[i - 1][0]);
  return (1 - t) * r[i - 1][col] + t * r[i][col];
}

// --- The reference table ---

TEST(ReferenceTable, Is360To830nmAt1nmWithHalvedEnds) {
  EXPECT_EQ(ReferenceTable::kSize, 471u);
  EXPECT_EQ(ReferenceTable::wavelength(0), 360.0);
  EXPECT_EQ(ReferenceTable::wavelength(470), 830.0);
  double length = 0;
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    EXPECT_EQ(ReferenceTable::wavelength(k), 360.0 + static_cast<double>(k));
    length += ReferenceTable::trapezoid(k);
  }
  // The trapezoid weights integrate a constant 1 over 360..830 nm: 470 nm, exactly.
  EXPECT_EQ(length, 470.0);
  EXPECT_EQ(ReferenceTable::trapezoid(0), 0.5);
  EXPECT_EQ(ReferenceTable::trapezoid(1), 1.0);
  EXPECT_EQ(ReferenceTable::trapezoid(470), 0.5);
}

// --- Observers ---

TEST(Observer, LoadsBothStandardObserversOnThe1nmTable) {
  const Observer& o2 = Observer::get("cie1931");
  const Observer& o10 = Observer::get("cie1964");
  EXPECT_EQ(o2.name, "cie1931");
  EXPECT_EQ(o10.name, "cie1964");
  for (const Observer* o : {&o2, &o10})
    for (const auto& c : o->cmf) {
      ASSERT_EQ(c.size(), 471u);  // 360..830 nm at 1 nm
      for (double v : c) {
        EXPECT_GE(v, 0.0);  // colour-matching functions are non-negative
      }
    }
  // Published CIE table values (CIE 015:2018 tables; exact in the data, so 1e-12).
  EXPECT_NEAR(o2.cmf[1][at(555)], 1.0, 1e-12);  // ybar peaks at 555 nm with value 1
  EXPECT_NEAR(o2.cmf[0][at(600)], 1.0622, 1e-12);
  EXPECT_NEAR(o2.cmf[2][at(445)], 1.7826, 1e-12);
  EXPECT_NEAR(o10.cmf[1][at(555)], 0.99911, 1e-12);
  EXPECT_NEAR(o10.cmf[0][at(600)], 1.12399, 1e-12);
  // Aliases resolve to the same cached tables.
  EXPECT_EQ(&Observer::get("CIE1931"), &o2);
  EXPECT_EQ(&Observer::get("cie1964_10"), &o10);
}

TEST(Observer, YIntegralIsPbrtsConstant) {
  const Observer& o2 = Observer::get("cie1931");
  // pbrt-v4's CIE_Y_integral = 106.856895 (sum of ybar on the 1 nm table); 1e-3 covers the
  // trapezoid's halved end points (ybar there is ~4e-6).
  EXPECT_NEAR(o2.y_integral, 106.856895, 1e-3);
  // And it is K = sum tau ybar as docs/DESIGN.md §3 defines it, to summation rounding.
  for (const char* name : {"cie1931", "cie1964"}) {
    const Observer& o = Observer::get(name);
    EXPECT_NEAR(o.y_integral, test::y_integral(o), 1e-12 * o.y_integral) << name;
  }
  // Mitsuba's observer divides by Mitsuba's constant (MI_CIE_Y_NORMALIZATION = 1 /
  // 106.7502593994140625, in mitsuba/core/spectrum.h), though its ybar integrates to 106.857.
  EXPECT_EQ(Observer::get("cie1931_mitsuba").y_integral, 106.7502593994140625);
  EXPECT_NEAR(test::y_integral(Observer::get("cie1931_mitsuba")), 106.857, 1e-3);
}

TEST(Observer, UnknownNameListsTheValidOnes) {
  expect_error_mentioning([] { (void)Observer::get("cie2006"); }, {"cie2006", "cie1931", "cie1964"},
                          "unknown observer");
}

TEST(Observer, EveryAliasAndListedNameResolvesToItsTable) {
  const Observer& o2 = Observer::get("cie1931");
  const Observer& o10 = Observer::get("cie1964");
  for (const char* alias : {"cie1931", "CIE1931", "cie1931_2", "1931", "2"}) {
    EXPECT_EQ(&Observer::get(alias), &o2) << alias;
  }
  for (const char* alias : {"cie1964", "Cie1964", "cie1964_10", "CIE1964_10", "1964", "10"}) {
    EXPECT_EQ(&Observer::get(alias), &o10) << alias;
  }
  // The listed names are the canonical ones, and each resolves to the observer of that name.
  ASSERT_EQ(Observer::names(), (std::vector<std::string>{"cie1931", "cie1931_mitsuba", "cie1964"}));
  for (const std::string& name : Observer::names()) {
    EXPECT_EQ(Observer::get(name).name, name);
  }
}

TEST(Observer, TablesAreTheCsvFilesOfData) {
  // The colour-matching functions are data/'s 1 nm tables as stored, bit for bit (strtod and
  // the library's parser both round correctly).
  for (const auto& [name, file] : {std::pair{"cie1931", "cie1931_2deg_cmf_1nm.csv"},
                                   std::pair{"cie1964", "cie1964_10deg_cmf_1nm.csv"}}) {
    SCOPED_TRACE(name);
    const Csv csv = read_csv(file);
    ASSERT_EQ(csv.rows.size(), 471u);
    const Observer& o = Observer::get(name);
    for (std::size_t k = 0; k < 471; ++k) {
      ASSERT_EQ(csv.rows[k][0], 360.0 + static_cast<double>(k));
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(o.cmf[c][k], csv.rows[k][1 + c]) << "nm " << 360 + k << " column " << c;
      }
    }
  }
}

// Mitsuba 3's colour matching: the 1931 table's values at its 5 nm points, linear between
// them; at 502.5 nm ybar is the mean of 500 and 505 nm's (0.323, 0.4073), which Mitsuba
// 3.9.1's cie1931_xyz(502.5) returns (0.36515); the 1 nm table there holds 0.3584.
TEST(Observer, TheFiveNanometreObserverIsTheTableLinearBetweenItsFiveNanometrePoints) {
  const Csv csv = read_csv("cie1931_2deg_cmf_1nm.csv");
  const Observer& o = Observer::get("cie1931_mitsuba");
  for (std::size_t k = 0; k < 471; ++k) {
    const std::size_t a = k / 5 * 5, b = std::min<std::size_t>(a + 5, 470);
    const double t = b == a ? 0 : static_cast<double>(k - a) / 5.0;
    for (int c = 0; c < 3; ++c) {
      const double want = (1 - t) * csv.rows[a][1 + c] + t * csv.rows[b][1 + c];
      ASSERT_NEAR(o.cmf[c][k], want, 1e-15) << "nm " << 360 + k << " column " << c;
    }
  }
  EXPECT_NEAR(0.5 * (o.cmf[1][at(502)] + o.cmf[1][at(503)]), 0.36515, 1e-6);
  EXPECT_EQ(o.cmf[1][at(555)], 1.0);
}

TEST(Observer, ParseErrorsAreNotSilentlyAnotherObserver) {
  // Near misses of a valid name are refused, naming what was given and the valid names.
  for (const char* bad : {"", "cie193", "cie1931 ", "1931_2", "cie2006_2"}) {
    expect_error_mentioning([bad] { (void)Observer::get(bad); }, {"cie1931", "cie1964"}, bad);
  }
}

// --- Illuminants ---

TEST(Illuminant, StandardIlluminantsLoadOnTheReferenceTable) {
  for (const char* name : {"D65", "D50", "A", "E", "C", "FL2", "FL11", "D55"}) {
    SCOPED_TRACE(name);
    Illuminant il = Illuminant::get(name);
    ASSERT_EQ(il.spd.size(), 471u);
    for (double v : il.spd) {
      EXPECT_TRUE(std::isfinite(v));
      EXPECT_GE(v, 0.0);  // a spectral power distribution is non-negative
    }
  }
  EXPECT_EQ(Illuminant::get("d65").name, "D65");  // names are case-insensitive
}

TEST(Illuminant, TablesAreNormalisedTo100At560nm) {
  // CIE normalisation of D65, D50 and A: 100 at 560 nm (exact in the 1 nm tables, so 1e-6).
  for (const char* name : {"D65", "D50", "A"}) {
    EXPECT_NEAR(Illuminant::get(name).spd[at(560)], 100.0, 1e-6) << name;
  }
  // E is equal energy.
  for (double v : Illuminant::get("E").spd) {
    EXPECT_EQ(v, Illuminant::get("E").spd[0]);
  }
}

TEST(Illuminant, ChromaticitiesMatchCie015) {
  const Observer& o2 = Observer::get("cie1931");
  struct Case {
    const char* name;
    double x, y, tol;
  } cases[] = {
      // CIE 015:2018 Table T.3 / T.8 values (CIE 1931 2°). 1e-4 for the 1 nm tables (the
      // published values are rounded to 5 digits); 2e-4 for D55 (built here from S0..S2 at 5 nm,
      // interpolated to 1 nm, which shifts the 5th digit) and for C (5 nm table).
      {"D65", 0.31272, 0.32903, 1e-4}, {"A", 0.44757, 0.40745, 1e-4},
      {"D50", 0.34567, 0.35850, 1e-4}, {"E", 1.0 / 3, 1.0 / 3, 1e-4},
      {"D55", 0.33242, 0.34743, 2e-4}, {"C", 0.31006, 0.31616, 2e-4},
  };
  for (const auto& c : cases) {
    auto xy = chromaticity(illuminant_xyz(o2, Illuminant::get(c.name)));
    EXPECT_NEAR(xy[0], c.x, c.tol) << c.name;
    EXPECT_NEAR(xy[1], c.y, c.tol) << c.name;
  }
  // 10° observer: D65 is (0.31382, 0.33100) (CIE 015:2018 Table T.3).
  auto xy10 = chromaticity(illuminant_xyz(Observer::get("cie1964"), Illuminant::get("D65")));
  EXPECT_NEAR(xy10[0], 0.31382, 1e-4);
  EXPECT_NEAR(xy10[1], 0.33100, 1e-4);
}

TEST(Illuminant, UnknownNameListsTheValidOnes) {
  expect_error_mentioning([] { (void)Illuminant::get("D99x"); }, {"D99x", "D65", "FL2"},
                          "unknown illuminant");
  expect_error_mentioning([] { (void)Illuminant::get("D30"); }, {"D40"}, "daylight below 4000 K");
}

TEST(Illuminant, EveryListedNameResolvesToATableOfThatName) {
  const std::vector<std::string> names = Illuminant::names();
  EXPECT_GT(names.size(), 40u);
  for (const std::string& name : names) {
    if (name.find('<') != std::string::npos) continue;  // D<nn>, <T>K: placeholders
    SCOPED_TRACE(name);
    const Illuminant il = Illuminant::get(name);
    EXPECT_EQ(il.name, name);
    ASSERT_EQ(il.spd.size(), ReferenceTable::kSize);
    for (double v : il.spd) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0);
    }
    std::string lower = name;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    EXPECT_EQ(Illuminant::get(lower).name, name);  // case-insensitive
  }
}

TEST(Illuminant, TablesAreTheCsvFilesInterpolatedOntoTheReferenceTable) {
  // Each tabulated illuminant is its data/ table, linear between the table's points and held
  // at its end values beyond them (the fluorescent tables stop at 380 and 780 nm, C at 780 nm);
  // 1e-12 of the table's peak: the rounding of two ways of writing the interpolation.
  struct Case {
    const char* name;
    const char* file;
    const char* column;
  } cases[] = {{"D65", "cie_illuminant_d65_1nm.csv", "value"},
               {"D50", "cie_illuminant_d50_1nm.csv", "value"},
               {"A", "cie_illuminant_a_1nm.csv", "value"},
               {"C", "cie_illuminant_c_5nm.csv", "value"},
               {"FL2", "cie_illuminants_fl_hp_led_5nm.csv", "FL2"},
               {"FL3.15", "cie_illuminants_fl_hp_led_5nm.csv", "FL3.15"},
               {"LED-B1", "cie_illuminants_fl_hp_led_5nm.csv", "LED-B1"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Csv csv = read_csv(c.file);
    const std::size_t col = static_cast<std::size_t>(
        std::find(csv.header.begin(), csv.header.end(), c.column) - csv.header.begin());
    ASSERT_LT(col, csv.header.size());
    const Illuminant il = Illuminant::get(c.name);
    double peak = 0;
    for (const auto& row : csv.rows) peak = std::max(peak, row[col]);
    for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
      ASSERT_NEAR(il.spd[k], csv_at(csv, col, 360.0 + static_cast<double>(k)), 1e-12 * peak)
          << "nm " << 360 + k;
    }
  }
  // Two values read off the tables by hand: C at 362 nm is 0.6 x 12.9 + 0.4 x 17.2 (its 360 and
  // 365 nm rows), and FL3.15 below 380 nm is its 380 nm value, 300.
  EXPECT_NEAR(Illuminant::get("C").spd[at(362)], 14.62, 1e-12);
  EXPECT_EQ(Illuminant::get("FL3.15").spd[at(360)], 300.0);
  EXPECT_EQ(Illuminant::get("C").spd[at(830)], 59.1);  // its 780 nm value, held
}

TEST(Illuminant, FNamesAreTheFluorescentTables) {
  for (int k = 1; k <= 12; ++k) {
    // (Appended rather than "F" + to_string: GCC 12's -Wrestrict misfires on the latter.)
    const std::string number = std::to_string(k);
    const std::string f_name = std::string("F").append(number);
    const std::string fl_name = std::string("FL").append(number);
    const Illuminant f = Illuminant::get(f_name);
    const Illuminant fl = Illuminant::get(fl_name);
    EXPECT_EQ(f.name, fl_name);
    EXPECT_EQ(f.spd, fl.spd) << k;
  }
  EXPECT_EQ(Illuminant::get("f11").name, "FL11");
  // There is no FL13: F13 is unknown, not some other table.
  expect_error_mentioning([] { (void)Illuminant::get("F13"); }, {"F13", "FL12"}, "F13");
}

// The CIE daylight locus: x_D of a correlated colour temperature (with the 1968 change of c2,
// T x 1.4388 / 1.4380) and y_D = -3 x_D^2 + 2.870 x_D - 0.275 (CIE 015:2018, section 4.1).
double daylight_x(double cct) {
  const double t = cct * 1.4388 / 1.4380;
  return t <= 7000 ? -4.6070e9 / (t * t * t) + 2.9678e6 / (t * t) + 0.09911e3 / t + 0.244063
                   : -2.0064e9 / (t * t * t) + 1.9018e6 / (t * t) + 0.24748e3 / t + 0.237040;
}

TEST(Illuminant, DaylightSeriesLiesOnTheDaylightLocus) {
  // D40..D250 are made from S0..S2 (5 nm, interpolated to 1 nm): their CIE 1931 chromaticity is
  // the locus' to 3e-4 (the 5 nm basis and its interpolation move the 4th digit).
  const Observer& o2 = Observer::get("cie1931");
  for (int hundreds : {40, 45, 55, 60, 75, 100, 150, 250}) {
    const std::string name = std::string("D").append(std::to_string(hundreds));
    SCOPED_TRACE(name);
    const Illuminant il = Illuminant::get(name);
    EXPECT_EQ(il.name, name);
    const auto xy = chromaticity(illuminant_xyz(o2, il));
    const double xd = daylight_x(100.0 * hundreds);
    EXPECT_NEAR(xy[0], xd, 3e-4);
    EXPECT_NEAR(xy[1], -3.0 * xd * xd + 2.870 * xd - 0.275, 3e-4);
  }
  // D75 as CIE 015:2018 Table T.3 gives it: (0.29902, 0.31485).
  const auto d75 = chromaticity(illuminant_xyz(o2, Illuminant::get("d75")));
  EXPECT_NEAR(d75[0], 0.29902, 2e-4);
  EXPECT_NEAR(d75[1], 0.31485, 2e-4);
}

TEST(Illuminant, DaylightOutside4000To25000KIsRefusedNamingTheRange) {
  for (const char* bad : {"D39", "D251", "D0", "D999"}) {
    expect_error_mentioning([bad] { (void)Illuminant::get(bad); }, {bad, "D40..D250"}, bad);
  }
}

// Planck's law as CIE 015:2018 writes it (section 3.1: c2 = 1.4388e-2 m K), relative.
double planck(double nm, double kelvin) {
  const double l = nm * 1e-9;
  return std::pow(l, -5) / (std::exp(1.4388e-2 / (l * kelvin)) - 1);
}

TEST(Illuminant, APlanckianRadiatorIsPlancksLawAt100At560nm) {
  for (double kelvin : {1000.0, 2856.0, 3200.0, 6500.0, 25000.0}) {
    SCOPED_TRACE(kelvin);
    const Illuminant il = Illuminant::get(std::to_string(static_cast<int>(kelvin)) + "K");
    ASSERT_EQ(il.spd.size(), ReferenceTable::kSize);
    for (std::size_t k = 0; k < ReferenceTable::kSize; k += 7) {
      const double nm = ReferenceTable::wavelength(k);
      EXPECT_NEAR(il.spd[k], 100.0 * planck(nm, kelvin) / planck(560.0, kelvin),
                  1e-12 * std::max(1.0, il.spd[k]))
          << nm << " nm";
    }
  }
  EXPECT_EQ(Illuminant::get("3200k").name, "3200K");
  EXPECT_EQ(Illuminant::get("2856.5K").name, "2856.5K");
  EXPECT_EQ(Illuminant::get("03200K").name, "3200K");
}

TEST(Illuminant, A2856KRadiatorHasIlluminantAsChromaticity) {
  // Illuminant A is a Planckian radiator at 2856 K (CIE 015:2018 Table T.3: 0.44757, 0.40745;
  // its defining formula uses the older c2, 1.435e-2 m K at 2848 K: the 5th digit differs).
  const auto xy = chromaticity(illuminant_xyz(Observer::get("cie1931"), Illuminant::get("2856K")));
  EXPECT_NEAR(xy[0], 0.44757, 1e-4);
  EXPECT_NEAR(xy[1], 0.40745, 1e-4);
}

TEST(Illuminant, APlanckianRadiatorOutside1000To25000KIsRefusedNamingTheRange) {
  for (const char* bad : {"999K", "25001K", "0K"}) {
    expect_error_mentioning([bad] { (void)Illuminant::get(bad); }, {bad, "1000..25000 K"}, bad);
  }
  for (const char* unknown : {"K", "-3200K", "0x10K", "3200 K", "3200KK", "3e3K"}) {
    SCOPED_TRACE(unknown);
    if (std::string_view(unknown) == "3e3K") {
      EXPECT_EQ(Illuminant::get(unknown).name, "3000K");  // a decimal number, as elsewhere
      continue;
    }
    expect_error_mentioning([unknown] { (void)Illuminant::get(unknown); }, {unknown, "<T>K"},
                            "unknown illuminant");
  }
}

// --- The embedded CSV tables ---

TEST(EmbeddedData, EveryCsvOfDataIsEmbeddedAsStored) {
  // The set of files is data/'s CSV files, and each column reads back as the file holds it.
  std::vector<std::string> on_disk, embedded;
  for (const auto& e : std::filesystem::directory_iterator(SPECTRALIZE_DATA_DIR))
    if (e.path().extension() == ".csv") on_disk.push_back(e.path().filename().string());
  for (const auto& f : embedded::data_files()) embedded.emplace_back(f.name);
  std::sort(on_disk.begin(), on_disk.end());
  std::sort(embedded.begin(), embedded.end());
  EXPECT_EQ(embedded, on_disk);
  for (const std::string& file : embedded) {
    SCOPED_TRACE(file);
    const Csv csv = read_csv(file);
    ASSERT_EQ(csv.header.at(0), "wavelength_nm");
    const std::vector<std::string> columns = embedded_columns(file);
    ASSERT_EQ(columns, std::vector<std::string>(csv.header.begin() + 1, csv.header.end()));
    // Column by column, and the whole table in one parse.
    const EmbeddedTable table = embedded_table(file);
    ASSERT_EQ(table.names, columns);
    ASSERT_EQ(table.wavelengths.size(), csv.rows.size());
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const auto [nm, values] = embedded_column(file, columns[c]);
      ASSERT_EQ(nm.size(), csv.rows.size());
      ASSERT_EQ(table.columns.at(c).size(), csv.rows.size());
      for (std::size_t r = 0; r < csv.rows.size(); ++r) {
        ASSERT_EQ(nm[r], csv.rows[r][0]);
        ASSERT_EQ(values[r], csv.rows[r][1 + c]) << columns[c] << " row " << r;
        ASSERT_EQ(table.wavelengths[r], csv.rows[r][0]);
        ASSERT_EQ(table.columns[c][r], csv.rows[r][1 + c]) << columns[c] << " row " << r;
      }
    }
  }
}

TEST(EmbeddedData, AColumnOnTheReferenceTableIsInterpolatedAndHeldAtItsEnds) {
  // The ColorChecker's white patch (5 nm, 380..780 nm): its rows at the 5 nm points, linear in
  // between, its end rows beyond; 1e-12 of the value.
  const char* file = "colorchecker_n_ohta_5nm.csv";
  const char* column = "white 9.5 (.05 D)";
  const auto [nm, rho] = embedded_column(file, column);
  const std::vector<double> ref = embedded_column_on_reference(file, column);
  ASSERT_EQ(ref.size(), ReferenceTable::kSize);
  ASSERT_EQ(nm.front(), 380.0);
  ASSERT_EQ(nm.back(), 780.0);
  for (int w = 360; w <= 830; ++w) {
    double want;
    if (w <= 380) {
      want = rho.front();
    } else if (w >= 780) {
      want = rho.back();
    } else {
      const std::size_t i = static_cast<std::size_t>((w - 380) / 5);
      const double t = (w - 380 - 5.0 * static_cast<double>(i)) / 5.0;
      want = t == 0 ? rho[i] : (1 - t) * rho[i] + t * rho[i + 1];
    }
    EXPECT_NEAR(ref[at(w)], want, 1e-12 * want) << w << " nm";
  }
}

TEST(EmbeddedData, MissingFilesAndColumnsAreErrorsNamingThem) {
  expect_error_mentioning([] { (void)embedded_column("nope.csv", "value"); }, {"nope.csv"},
                          "missing file");
  expect_error_mentioning([] { (void)embedded_columns("nope.csv"); }, {"nope.csv"},
                          "missing file (columns)");
  expect_error_mentioning([] { (void)embedded_table("nope.csv"); }, {"nope.csv"},
                          "missing file (table)");
  expect_error_mentioning(
      [] { (void)embedded_column_on_reference("cie_illuminant_a_1nm.csv", "vlaue"); },
      {"cie_illuminant_a_1nm.csv", "vlaue"}, "missing column");
  // The wavelength column is the abscissa, not a data column.
  expect_error_mentioning(
      [] { (void)embedded_column("cie_illuminant_a_1nm.csv", "wavelength_nm"); }, {"wavelength_nm"},
      "the wavelength column");
}

}  // namespace
}  // namespace spectralize
