#pragma once
// The boundary-aware exact table (docs/DESIGN.md §14): node spectra on a grid of coordinates
// that are linear in the colour (reflectance: the RGB of a frame; emission: CIE xy with
// X+Y+Z as the scale), cut into simplices whose barycentric blend reproduces every colour of
// the gamut exactly and stays within the bounds, with no solver once the nodes are made.
//
// - Cells wholly inside the gamut (every corner in it: the gamut is convex) are split into
//   Kuhn simplices (6 tetrahedra, sorting the fractional coordinates; 2 triangles in 2-D).
// - Cells that cross the boundary are clipped to the gamut and cut into simplices whose
//   vertices are the corners inside and points on the boundary, whose exact spectra are
//   known in closed form (core/gamut_boundary.h).
// - Cells outside have nothing: their colours are mapped into the gamut first (docs/DESIGN.md
//   §5) by the caller.
// Node spectra are the spectralizer's (its model); a node whose solve is not exact is made
// exact by construction instead: the blend of the grey (or white light) of its luminance and
// the boundary point on the ray through it.
//
// Cells and nodes are built on first use by any thread (the image paths), or all at once for a
// render-time table file (core/table_file.h).

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
#include <vector>

#include "core/colorimetry/mat3.h"
#include "core/gamut/gamut_boundary.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// Node spacing of an exact table (docs/DESIGN.md §14, chosen by measurement; see
/// docs/guide/conventions.md).
struct TableResolution {
  int steps = 24;          // reflectance: node intervals on [0, 1] per axis, at (k / steps)^2
  int coarse_steps = 8;    // reflectance: outside [0, 1], at least this many per unit
  int chroma_steps = 128;  // emission: node intervals per unit of x and of y
};

/// A loop over [0, n) in chunks, possibly in parallel: calls body(begin, end) for disjoint
/// ranges covering it. The core library has no thread pool; the io layer passes OIIO's.
using ParallelFor =
    std::function<void(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body)>;

/// The frame matrix with its white snapped: when M (1, 1, 1) is D65 to within 1e-5 (a float
/// measurement through OCIO), the rows are scaled so that it is kWhiteD65 exactly, and RGB
/// (1, 1, 1) lands exactly on the solid's white vertex. Cost: O(1).
Mat3 snap_frame_white(const Mat3& rgb_to_xyz);

/// One blend of a colour: up to four vertices, each a node spectrum or a boundary spectrum.
struct TableBlend {
  std::array<const float*, 4> dense{};                // N floats, or null
  std::array<const BoundarySpectrum*, 4> boundary{};  // when dense is null
  std::array<float, 4> weight{};
  int count = 0;
};

/// Counters of the table's work, for reports. Plain numbers, summed over threads.
struct ExactTableStats {
  std::uint64_t nodes_computed = 0;     // node spectra solved (or constructed) in this run
  std::uint64_t nodes_loaded = 0;       // node spectra adopted from storage
  std::uint64_t nodes_outside = 0;      // grid nodes outside the gamut (no spectrum)
  std::uint64_t nodes_boundary = 0;     // nodes on the boundary (closed form, no solve)
  std::uint64_t nodes_constructed = 0;  // nodes whose model solve was not exact: constructed
  std::uint64_t boundary_cells = 0;     // cells clipped to the gamut
};

class ExactTable {
 public:
  /// A table for `spectralizer` (kept by reference; must outlive the table). `frame` is the
  /// RGB -> CIE XYZ (D65) matrix of the reflectance coordinates (its white snapped, see
  /// snap_frame_white); emission tables do not depend on it. Cost: the solid's facets
  /// (O(N^3), ~2 ms at 5 nm) and a pointer per node and per cell; no solves until used.
  ExactTable(const Spectralizer& spectralizer, const Mat3& frame, TableResolution res = {});
  ~ExactTable();
  ExactTable(const ExactTable&) = delete;
  ExactTable& operator=(const ExactTable&) = delete;

  /// The blend of a target (the mode's terms: white balanced) when it is in the gamut; false
  /// when it is outside (to be mapped by the caller) or not finite. `nearest`: for a target the
  /// caller knows to be inside (within the gamut's rounding), the nearest simplex of its cell,
  /// weights clamped. Emission weights include the target's X+Y+Z. Thread-safe. Cost: O(1)
  /// inside a built cell; building a cell costs its nodes' solves (~40 us each at 5 nm) and,
  /// at the boundary, a clip (~O(facets)).
  bool locate(const Xyz& target, TableBlend& blend, bool nearest = false);
  /// out[0..N) = sum of weight x vertex spectrum; reflectances clamped to <= 1 (an ulp of
  /// rounding). out must not alias the table. Cost: O(N x count).
  void blend_into(const TableBlend& blend, float* out) const;

  /// Builds every node and cell, nodes first, through `parallel` (serial when empty).
  /// Cost: every node's solve, ~40 us each at 5 nm (O(nodes) / threads), and the clips.
  void build(const ParallelFor& parallel = {});

  /// "exact table 1; reflectance frame ...; steps 24/8" or "...; emission chroma 1/128": with
  /// the spectral settings, what the nodes depend on. Cost: O(1).
  std::string layout() const;
  /// Work done so far. Cost: O(1).
  ExactTableStats stats() const;
  /// Samples per spectrum. Cost: O(1).
  std::size_t bands() const { return bands_; }
  /// Grid nodes (computed or not). Cost: O(1).
  std::size_t node_count() const { return nodes_.size(); }
  /// True when nodes were solved since construction (worth saving). Cost: O(1).
  bool dirty() const { return stats_.computed.load() > 0; }
  /// Calls fn(index, values) for every node solved (or adopted) so far; nodes made in closed
  /// form or outside are not listed (they are remade cheaply). Not to be run concurrently
  /// with build(). Cost: O(nodes).
  void for_each_solved_node(
      const std::function<void(std::size_t, std::span<const float>)>& fn) const;
  /// Installs a stored node after checking that it lies strictly inside the gamut, its values
  /// are within the mode's bounds and it reproduces its own colour (relative XYZ 1e-5: float
  /// storage); a node the table has is kept. False, installing nothing, otherwise.
  /// Thread-safe. Cost: O(N + facets).
  bool adopt_node(std::size_t index, std::span<const float> values);

  // --- What a table file holds (core/table_file.h); call after build() ---

  /// The node positions of axis a (emission: x, y, and one position on axis 2). Cost: O(1).
  const std::vector<double>& axis(int a) const { return axes_[a]; }
  /// The node spacing it was made with. Cost: O(1).
  TableResolution resolution() const { return res_; }
  /// True for a reflectance table. Cost: O(1).
  bool reflectance() const { return reflectance_; }
  /// The node's spectrum (N floats) or null when outside the gamut (or not built). Cost: O(1).
  const float* node_spectrum(std::size_t index) const;
  /// The matrix from the frame's RGB to targets (the white balanced frame; reflectance
  /// coordinates are this RGB),
  /// and its inverse. Cost: O(1).
  const Mat3& target_from_rgb() const { return target_from_u_; }
  const Mat3& rgb_from_target() const { return u_from_target_; }
  /// The frame's RGB -> XYZ (D65) matrix (white snapped). Cost: O(1).
  const Mat3& frame() const { return frame_; }

  /// A point on the gamut's boundary that is a vertex of a clipped cell, with its exact
  /// spectrum.
  struct BoundaryVertex {
    Xyz position;
    BoundarySpectrum spectrum;
  };
  /// A simplex of a clipped cell: each vertex a corner of the cell (0..7: bit 0 x, bit 1 y,
  /// bit 2 z upper) or, with kBoundaryVertex set, one of the cell's boundary vertices (its
  /// index in the low bits); `map`: its barycentric affine map (core/cell_clipping.h).
  struct Simplex {
    std::array<std::uint32_t, 4> vertex;
    std::array<double, 12> map;
  };
  struct BoundaryCell {
    std::vector<Simplex> simplices;
    std::vector<BoundaryVertex> vertices;
  };
  static constexpr std::uint32_t kBoundaryVertex = 0x80000000u;
  enum class CellKind { inside, boundary, outside };
  /// Number of cells. Cost: O(1).
  std::size_t cell_count() const { return cells_.size(); }
  /// The kind of built cell `index` and, for a boundary cell, its data. Cost: O(1).
  CellKind cell(std::size_t index, const BoundaryCell** data = nullptr) const;

 private:
  bool cell_blend(const int i[3], const double f[3], const Xyz& u, double scale, TableBlend& b,
                  bool nearest);
  const float* node(std::size_t index);
  const float* compute_node(std::size_t index);
  const void* build_cell(std::size_t index);
  Xyz node_coords(std::size_t index) const;
  Xyz node_target(std::size_t index) const;
  double distance(const Xyz& coords, std::size_t* facet) const;
  BoundarySpectrum boundary_spectrum(const Xyz& coords) const;
  std::vector<double> constructed_spectrum(const Xyz& coords) const;
  float* store(std::span<const double> values);
  int find_interval(int a, double u) const;

  const Spectralizer& sp_;
  bool reflectance_;
  std::size_t bands_;
  TableResolution res_;
  Mat3 frame_, target_from_u_, u_from_target_;
  std::unique_ptr<SolidBoundary> solid_;
  std::unique_ptr<LocusBoundary> locus_;
  double eps_ = 1e-12;
  std::array<std::vector<double>, 3> axes_;
  int nx_ = 0, ny_ = 0, nz_ = 0;

  std::vector<std::atomic<const float*>> nodes_;
  std::vector<std::atomic<const void*>> cells_;
  std::array<std::mutex, 64> locks_;       // node builds
  std::array<std::mutex, 64> cell_locks_;  // cell builds
  std::mutex arena_mutex_;
  std::deque<std::vector<float>> arena_;
  std::size_t arena_used_ = 0;
  std::mutex boundary_mutex_;
  std::deque<BoundaryCell> boundary_cells_;

  struct AtomicStats {
    std::atomic<std::uint64_t> computed{0}, loaded{0}, outside{0}, boundary{0}, constructed{0},
        cells{0};
  };
  AtomicStats stats_;
  std::vector<std::uint8_t> solved_;  // per node: 1 when solved or adopted (worth saving)
};

}  // namespace spectralize
