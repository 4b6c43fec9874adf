#pragma once
// CIE observers and illuminants on the 1 nm reference table grid 360..830 nm (docs/DESIGN.md §3),
// loaded from the project's embedded copy of data/.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

/// The reference table grid: 360..830 nm at 1 nm, 471 points.
struct ReferenceTable {
  static constexpr double kStartNm = 360.0;
  static constexpr std::size_t kSize = 471;
  /// Wavelength of table point k. Cost: O(1).
  static constexpr double wavelength(std::size_t k) { return kStartNm + static_cast<double>(k); }
  /// Trapezoid weight of table point k (1 nm, halved at both ends). Cost: O(1).
  static constexpr double trapezoid(std::size_t k) {
    return (k == 0 || k == kSize - 1) ? 0.5 : 1.0;
  }
};

/// A CIE standard observer: colour-matching functions xbar, ybar, zbar on the reference table.
struct Observer {
  std::string name;                        // "cie1931", "cie1931_mitsuba" or "cie1964"
  std::array<std::vector<double>, 3> cmf;  // xbar, ybar, zbar, ReferenceTable::kSize each
  double y_integral = 0;                   // K = sum_k tau_k ybar_k (pbrt's CIE_Y_integral)

  /// The observer named `name` (cie1931 | cie1931_2 | cie1931_mitsuba | cie1964 | cie1964_10,
  /// case-insensitive; cie1931_mitsuba: the 1931 table at its 5 nm points, linear between
  /// them, with Mitsuba 3's Y normalisation: as Mitsuba 3 integrates); throws Error listing the
  /// valid names. Parsed once and cached. Cost: O(1) after first use.
  static const Observer& get(std::string_view name);
  /// Canonical observer names. Cost: O(1).
  static std::vector<std::string> names();
};

/// A CIE illuminant's relative spectral power on the reference table.
struct Illuminant {
  static constexpr double kMinPlanckianKelvin = 1000;
  static constexpr double kMaxPlanckianKelvin = 25000;

  std::string name;         // canonical name, e.g. "D65"
  std::vector<double> spd;  // ReferenceTable::kSize values

  /// The illuminant `name` (case-insensitive): D65, D50, A, C, E, D<cct/100> (e.g. D55, D75;
  /// daylight series from S0..S2), <T>K (e.g. 3200K: a Planckian radiator by Planck's law,
  /// c2 = 1.4388e-2 m K, kMinPlanckianKelvin..kMaxPlanckianKelvin), FL1..FL12 (also F1..F12),
  /// FL3.1..FL3.15, HP1..HP5, LED-*. Tables given only on 380..780 nm or at 5 nm are interpolated
  /// linearly and extended by their end values (CIE 015's advice). Throws Error listing the names.
  /// Cost: O(table) per call.
  static Illuminant get(std::string_view name);
  /// All accepted illuminant names (D-series besides D50/D65 as "D<nn>"). Cost: O(names).
  static std::vector<std::string> names();
};

/// A column of a CSV table in data/, resampled linearly onto the reference table and extended by
/// its end values; throws Error if missing. Cost: O(rows).
std::vector<double> embedded_column_on_reference(std::string_view file, std::string_view column);

/// Wavelengths and one column of an embedded CSV table, as stored. Cost: O(rows).
std::pair<std::vector<double>, std::vector<double>> embedded_column(std::string_view file,
                                                                    std::string_view column);

/// Names of the data columns (all but wavelength_nm) of an embedded CSV table. Cost: O(cols).
std::vector<std::string> embedded_columns(std::string_view file);

/// Every column of an embedded CSV table, as stored: the wavelengths and, per data column in
/// the file's order, its name and values (an empty cell is 0). Throws Error for a malformed
/// table. Cost: O(rows x columns), one parse.
struct EmbeddedTable {
  std::vector<double> wavelengths;
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
};
EmbeddedTable embedded_table(std::string_view file);

}  // namespace spectralize
