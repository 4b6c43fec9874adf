#pragma once
// The quantize-and-cache table of docs/DESIGN.md §4: node spectra computed by the exact
// spectralizer on a grid of colour coordinates, filled lazily and shared by all threads, and
// interpolated with weights that reproduce linear functions, so every pixel's spectrum still
// reproduces its colour exactly (to float precision).
//
// Emission spectra scale with the colour, so nodes sit on the chromaticity plane (x, y) with
// X+Y+Z = 1 and a pixel is the bilinear blend times its X+Y+Z. Reflectances are not scale-free
// (the bound rho <= 1), so their nodes add the axis S = X+Y+Z: XYZ = S (x, y, 1-x-y) is
// multilinear in (x, y, S), so trilinear blending is exact too. A cell with a node outside the
// gamut (the locus, or the reflectance solid) falls back to a direct exact solve of the pixel,
// cached by its colour.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/spectralizer.h"

namespace spectralize {

/// What happened to one pixel.
enum class PixelKind : std::uint8_t {
  in_gamut,       // exact spectrum of the pixel's colour
  black,          // zero colour: zero spectrum
  invalid,        // NaN or infinite: zero spectrum
  negative,       // negative luminance (Y < 0): no light or surface has it; zero spectrum
  outside_locus,  // outside the spectral locus: mapped (docs/DESIGN.md §5), then exact
  outside_solid,  // reflectance outside the reflectance solid: mapped, then exact
};

/// How the spectrum of one pixel was made.
struct PixelResult {
  PixelKind kind = PixelKind::in_gamut;
  bool fallback =
      false;   // a direct exact solve (cell with an out-of-gamut node, or --method exact)
  Xyz target;  // the colour the spectrum reproduces (mode's terms, gamut mapped)
};

/// Counters of a table's work, for reports. Plain numbers, summed over threads.
struct TableStats {
  std::uint64_t nodes_computed = 0;    // node spectra solved in this run
  std::uint64_t nodes_loaded = 0;      // node spectra read from the persistent cache
  std::uint64_t nodes_infeasible = 0;  // nodes outside the gamut (their cells fall back)
  std::uint64_t fallback_solves = 0;   // direct exact solves of pixels
  std::uint64_t fallback_hits = 0;     // pixels answered from the direct-solve cache
};

class SpectralTable {
 public:
  enum class Method { table, exact };

  /// A table for `spectralizer` (kept by reference; must outlive the table). `exact`: every
  /// distinct colour is solved directly (no interpolation). Cost: a pointer per node (~0.1 MB
  /// emission, ~0.4 MB reflectance); no solves until used.
  SpectralTable(const Spectralizer& spectralizer, Method method = Method::table);

  /// The spectra of n pixels (CIE XYZ, D65-adapted): pixel i's N samples go to
  /// out + i * stride (stride >= N; 0 means N), results has n entries. Reflectances stay in
  /// [0, 1] bit-exactly. Thread-safe. Cost: ~N multiply-adds per node blended (4 or 8), a node
  /// solve (~40 us at 5 nm) on first use of a node, a direct solve for pixels in cells that
  /// cross the gamut boundary.
  void spectra(const Xyz* xyz_d65, std::size_t n, float* out, PixelResult* results,
               std::size_t stride = 0);

  /// Work done so far. Cost: O(1).
  TableStats stats() const;

  /// The node grid as text ("nodes 96x111x1 step 1/128 S/16"): with the spectral settings,
  /// what a persisted table depends on. Cost: O(1).
  std::string layout() const;
  /// Samples per node spectrum. Cost: O(1).
  std::size_t bands() const { return bands_; }
  /// Number of nodes of the grid (computed or not). Cost: O(1).
  std::size_t node_count() const { return node_count_; }
  /// Calls fn(index, values) for every computed node, values empty for a node outside the gamut.
  /// Not to be run concurrently with spectra(). Cost: O(nodes).
  void for_each_node(const std::function<void(std::size_t, std::span<const float>)>& fn) const;
  /// Installs a node read from storage (values empty: outside the gamut) after checking that a
  /// feasible node reproduces its own colour (relative XYZ 1e-5: float storage) within the
  /// mode's bounds; a node the table already has is kept. Returns false, installing nothing,
  /// for an index out of range or a node that fails the check. Not to be run concurrently with
  /// spectra(). Cost: O(N).
  bool adopt_node(std::size_t index, std::span<const float> values);
  /// True when nodes were computed since construction (worth saving). Cost: O(1).
  bool dirty() const { return stats_.nodes_computed.load() > 0; }

 private:
  static constexpr double kXMax = 0.76, kYMax = 0.86;  // the spectral locus fits inside

  // One pixel into `res` (written in place: a returned struct assembled on the stack stalls on
  // store forwarding in the batch loop).
  [[gnu::always_inline]] void pixel(const Xyz& xyz_d65, float* out, PixelResult& res);

  // Node storage: a pointer per node, null until computed; kInfeasible marks nodes outside.
  const float* node(std::size_t index);
  const float* compute_node(std::size_t index);
  Xyz node_target(std::size_t index) const;
  PixelResult direct(const Xyz& target, float* out);
  float* allocate_node();

  const Spectralizer& sp_;
  Method method_;
  std::size_t bands_;
  int xy_steps_, s_steps_;
  int nx_, ny_, ns_;  // nodes per axis
  double s_max_ = 1;  // reflectance: S of the reference white, the top layer
  std::unique_ptr<std::atomic<const float*>[]> nodes_;
  std::size_t node_count_;
  static const float kInfeasibleMark;

  std::mutex arena_mutex_;
  std::deque<std::vector<float>> arena_;  // stable storage for node spectra, in blocks
  std::size_t arena_used_ = 0;
  std::array<std::mutex, 64> node_locks_;

  // Direct solves of single colours, keyed by the exact target, sharded to limit contention.
  struct TargetKey {
    double X, Y, Z;
    bool operator==(const TargetKey&) const = default;
  };
  struct TargetHash {
    std::size_t operator()(const TargetKey& k) const;
  };
  struct Solved {
    std::vector<float> values;
    PixelResult result;
  };
  struct Shard {
    std::mutex mutex;
    std::unordered_map<TargetKey, Solved, TargetHash> solved;
  };
  std::array<Shard, 64> shards_;

  struct AtomicStats {
    std::atomic<std::uint64_t> nodes_computed{0}, nodes_loaded{0}, nodes_infeasible{0},
        fallback_solves{0}, fallback_hits{0};
  };
  AtomicStats stats_;
};

}  // namespace spectralize
