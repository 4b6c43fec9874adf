#pragma once
// The table every image, --color and array conversion goes through (docs/DESIGN.md §4, §14):
// the boundary-aware exact table (core/exact_table.h), built lazily cell by cell and shared by
// all threads, so every colour's spectrum is an exact blend of precomputed node spectra, in
// gamut or mapped into it first (docs/DESIGN.md §5), with no per-colour solve; the same cells
// a render-time table file holds (core/table_file.h). Method::exact solves every distinct
// colour directly instead, for comparison.
//
// Reflectance cells live in the RGB of a frame: the input's colour space (its primaries), so
// that a texture's spectra are exactly those a renderer gets from that space's table file;
// emission cells in CIE xy, the same for every space.

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

#include "core/colorimetry/mat3.h"
#include "core/tables/exact_table.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// Linear Rec.709 (sRGB primaries, D65) -> CIE XYZ: the frame of tables whose colours come
/// from no RGB space (XYZ input, data without primaries).
inline constexpr Mat3 kRec709Frame = {
    0.41239079926595948, 0.35758433938387796, 0.18048078840183429,
    0.21263900587151036, 0.71516867876775593, 0.07219231536073372,
    0.01933081871559185, 0.11919477979462599, 0.95053215224966058};

/// How the spectrum of one pixel was made.
struct PixelResult {
  Outcome kind = Outcome::exact;  // what became of the pixel's colour
  bool fallback = false;          // a direct exact solve (--method exact)
  Xyz target;                     // the colour the spectrum reproduces (mode's terms, gamut mapped)
};

/// Counters of a table's work, for reports. Plain numbers, summed over threads.
struct TableStats {
  std::uint64_t nodes_computed = 0;     // node spectra solved in this run
  std::uint64_t nodes_loaded = 0;       // node spectra read from the persistent cache
  std::uint64_t nodes_infeasible = 0;   // grid nodes outside the gamut (no spectrum)
  std::uint64_t nodes_constructed = 0;  // nodes whose model solve was not exact: constructed
  std::uint64_t boundary_cells = 0;     // cells clipped to the gamut's boundary
  std::uint64_t fallback_solves = 0;    // direct exact solves of pixels (--method exact)
  std::uint64_t fallback_hits = 0;      // pixels answered from the direct-solve cache
};

class SpectralTable {
 public:
  enum class Method { table, exact };

  /// A table for `spectralizer` (kept by reference; must outlive the table) whose reflectance
  /// cells are in the RGB of `frame` (RGB -> CIE XYZ D65: the input's colour space). `exact`:
  /// every distinct colour is solved directly (no interpolation). Cost: the solid's facets
  /// (~2 ms at 5 nm) and a pointer per node and cell; no solves until used.
  SpectralTable(const Spectralizer& spectralizer, Method method = Method::table,
                const Mat3& frame = kRec709Frame);

  /// The spectra of n pixels (CIE XYZ, D65-adapted): pixel i's N samples go to
  /// out + i * stride (stride >= N; 0 means N), results has n entries. Reflectances stay in
  /// [0, 1] bit-exactly. Thread-safe. Cost: ~4 N multiply-adds per pixel; on first use of a
  /// cell its nodes' solves (~40 us each at 5 nm) and, at the gamut's boundary, a clip; a
  /// colour outside the gamut is mapped first (O(facets)).
  void spectra(const Xyz* xyz_d65, std::size_t n, float* out, PixelResult* results,
               std::size_t stride = 0);

  /// Work done so far. Cost: O(1).
  TableStats stats() const;

  /// The cells' layout as text (frame, spacing): with the spectral settings, what a persisted
  /// table depends on. Cost: O(1).
  std::string layout() const { return exact_.layout(); }
  /// Samples per node spectrum. Cost: O(1).
  std::size_t bands() const { return exact_.bands(); }
  /// Number of nodes of the grid (computed or not). Cost: O(1).
  std::size_t node_count() const { return exact_.node_count(); }
  /// Calls fn(index, values) for every node solved (or adopted); nodes outside the gamut or on
  /// its boundary (closed form) are remade cheaply and not listed. Not to be run concurrently
  /// with spectra(). Cost: O(nodes).
  void for_each_node(const std::function<void(std::size_t, std::span<const float>)>& fn) const {
    exact_.for_each_solved_node(fn);
  }
  /// Installs a node read from storage after checking that it lies inside the gamut, stays
  /// within the mode's bounds and reproduces its own colour (relative XYZ 1e-5: float storage);
  /// a node the table already has is kept. Returns false, installing nothing, otherwise.
  /// Not to be run concurrently with spectra(). Cost: O(N + facets).
  bool adopt_node(std::size_t index, std::span<const float> values) {
    return exact_.adopt_node(index, values);
  }
  /// True when nodes were computed since construction (worth saving). Cost: O(1).
  bool dirty() const { return exact_.dirty(); }

 private:
  // One pixel into `res` (written in place: a returned struct assembled on the stack stalls on
  // store forwarding in the batch loop).
  [[gnu::always_inline]] void pixel(const Xyz& xyz_d65, float* out, PixelResult& res);
  PixelResult direct(const Xyz& target, float* out);

  const Spectralizer& sp_;
  Method method_;
  std::size_t bands_;
  ExactTable exact_;
  // Emission: white light within float precision is the basis itself (as the Spectralizer
  // snaps it, docs/DESIGN.md §6), not a blend that differs in samples the eye barely sees.
  std::vector<float> basis_;
  Xyz basis_white_;

  // Direct solves of single colours (Method::exact), keyed by the exact target, sharded to
  // limit contention.
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
  std::atomic<std::uint64_t> fallback_solves_{0}, fallback_hits_{0};
};

}  // namespace spectralize
