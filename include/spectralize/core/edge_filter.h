#pragma once
// The paper's edge-peak filter: sort the admissible partial solutions by their largest density
// and drop the K largest (Zhdanov & Potemin, section 3). K is a count, a fraction of L, or
// "auto": per colour, the smallest fraction of a fixed ladder that leaves no edge peak (no
// sample within 20 nm of either end of the grid above the mean over 400-700 nm).

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

class EdgeFilter {
 public:
  enum class Kind { fraction, count, automatic };

  /// The fractions "auto" tries, in order, until the spectrum has no edge peak.
  static constexpr double kAutoLadder[] = {0.7, 0.8, 0.85, 0.9, 0.95, 0.98, 0.99};
  /// Width of the edge bands at both ends of the grid that "auto" keeps free of peaks (nm).
  static constexpr double kEdgeBandNm = 20.0;

  /// Drop nothing. Cost: O(1).
  EdgeFilter() = default;
  /// Drop `f` of the L partial solutions, 0 <= f < 1; throws Error otherwise. Cost: O(1).
  static EdgeFilter fraction(double f);
  /// Drop `k` partial solutions (always keeping at least one). Cost: O(1).
  static EdgeFilter count(std::size_t k);
  /// The smallest fraction of kAutoLadder that removes the edge peaks, per colour. Cost: O(1).
  static EdgeFilter automatic();
  /// Parses "auto", "0.7", "70%" (fractions), "1000" (a count) or "none"; throws Error.
  /// Cost: O(len).
  static EdgeFilter parse(std::string_view text);

  /// How many of L admissible partial solutions to drop (automatic: its first ladder step);
  /// keeps at least one. Cost: O(1).
  std::size_t drop_count(std::size_t admissible) const;
  Kind kind() const { return kind_; }
  double value() const { return value_; }
  /// "auto", "0.7" or "1000": parseable by parse(). Cost: O(1).
  std::string to_string() const;
  friend bool operator==(const EdgeFilter&, const EdgeFilter&) = default;

 private:
  Kind kind_ = Kind::fraction;
  double value_ = 0;
};

/// Where a grid's edge peaks are looked for: the samples within EdgeFilter::kEdgeBandNm of
/// either end, against the mean over the interior (400-700 nm, or everything outside the bands
/// for a grid that does not reach into it).
class EdgeBands {
 public:
  /// No bands: every spectrum is free of edge peaks. Cost: O(1).
  EdgeBands() = default;
  /// The bands of samples at `wavelengths` (nm, increasing). Cost: O(N).
  explicit EdgeBands(std::span<const double> wavelengths);

  /// True when no edge sample exceeds the interior mean. Cost: O(N).
  bool free_of_peaks(std::span<const double> spectrum) const;
  /// Mean of the spectrum over the interior samples. Cost: O(N).
  double interior_mean(std::span<const double> spectrum) const;
  /// Largest edge sample over the interior mean (0 for a zero interior). Cost: O(N).
  double edge_ratio(std::span<const double> spectrum) const;
  /// The samples of the edge bands. Cost: O(1).
  const std::vector<std::size_t>& edge_samples() const { return edge_; }

 private:
  std::vector<std::size_t> edge_, interior_;
};

}  // namespace spectralize
