#include "core/tables/exact_table.h"

#include <spectralize/rt_impl.hpp>  // closest_in_simplex, as the evaluator's boundary cells

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/gamut/cell_clipping.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

constexpr std::size_t kArenaBlockNodes = 1024;
// A stored node must reproduce its own colour to float precision (docs/DESIGN.md §4).
constexpr double kStoredNodeTolerance = 1e-5;
// Barycentric weights down to this below 0 are rounding: the point is in the simplex.
constexpr double kInsideWeight = 1e-12;
// A point whose best simplex has a weight below this is outside the clipped cell.
constexpr double kOutsideWeight = 1e-9;

const float kOutsideNode = 0.0f;
const char kInsideCell = 0, kOutsideCell = 0;

// Positions as float, so that a float evaluator's nodes are where the spectra were made.
double as_float(double v) {
  return static_cast<double>(static_cast<float>(v));
}

// Node positions on one reflectance axis: `steps` intervals on [0, 1], and beyond it, down to
// `lo` and up to `hi` (the solid's extent), intervals no longer than 1 / coarse_steps.
std::vector<double> reflectance_axis(double lo, double hi, int steps, int coarse_steps) {
  std::vector<double> axis;
  // A part of the solid beyond [0, 1] thinner than this is left out: its colours are mapped
  // by less than rounding (docs/DESIGN.md §5).
  constexpr double kThin = 1e-9;
  if (lo < -kThin) {
    const double length = -lo * (1 + 1e-9) + 1e-12;
    const int m = std::max(1, static_cast<int>(std::ceil(length * coarse_steps)));
    for (int k = 0; k < m; ++k) axis.push_back(as_float(-length + length * k / m));
  }
  // Squared positions: natural spectra change fastest near black, where linear RGB textures
  // also crowd (docs/DESIGN.md §14: the spacing measured against ΔE of the direct solves).
  for (int k = 0; k <= steps; ++k) {
    const double x = static_cast<double>(k) / steps;
    axis.push_back(as_float(x * x));
  }
  if (hi > 1 + kThin) {
    const double length = (hi - 1) * (1 + 1e-9) + 1e-12;
    const int m = std::max(1, static_cast<int>(std::ceil(length * coarse_steps)));
    for (int k = 1; k <= m; ++k) axis.push_back(as_float(1 + length * k / m));
  }
  return axis;
}

// Chromaticity nodes every 1 / steps through `origin` (the white of the emission basis: white
// light is a node, its spectrum the basis itself), covering [lo, hi]. In double, so that white
// is the node exactly (a float evaluator's nodes are within 3e-8 of these: a blend with its
// float weights is exact to ~1e-7).
std::vector<double> chroma_axis(double lo, double hi, int steps, double origin) {
  std::vector<double> axis;
  const int a = static_cast<int>(std::floor((lo - 1e-9 - origin) * steps));
  const int b = static_cast<int>(std::ceil((hi + 1e-9 - origin) * steps));
  for (int k = a; k <= b; ++k) axis.push_back(origin + static_cast<double>(k) / steps);
  return axis;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

Mat3 snap_frame_white(const Mat3& m) {
  const Xyz white = mul(m, Xyz{1, 1, 1});
  if (!(relative_error(white, kWhiteD65) <= 1e-5)) return m;
  return scale_rows({kWhiteD65.X / white.X, kWhiteD65.Y / white.Y, kWhiteD65.Z / white.Z}, m);
}

ExactTable::ExactTable(const Spectralizer& sp, const Mat3& frame, TableResolution res)
    : sp_(sp),
      reflectance_(sp.settings().mode == Mode::reflectance),
      bands_(sp.settings().grid.size()),
      res_(res),
      frame_(snap_frame_white(frame)) {
  if (res.steps < 1 || res.coarse_steps < 1 || res.chroma_steps < 1)
    throw Error("exact table: resolution must be positive");
  // The white balance of the mode (docs/DESIGN.md §3) applied to the frame: coordinates are
  // RGB, and targets are what the spectra reproduce.
  const Xyz balance = sp.target_of(Xyz{1, 1, 1});
  target_from_u_ = scale_rows(balance, frame_);
  if (!(std::abs(det(target_from_u_)) > 1e-12))
    throw Error("exact table: the colour space's RGB -> XYZ matrix is singular");
  u_from_target_ = inverse(target_from_u_);
  if (reflectance_) {
    solid_ = std::make_unique<SolidBoundary>(sp.weights().columns(), target_from_u_);
    for (int a = 0; a < 3; ++a)
      axes_[a] =
          reflectance_axis(solid_->lower()[a], solid_->upper()[a], res.steps, res.coarse_steps);
    eps_ = 1e-12;  // relative to the coordinates (see compute_node)
  } else {
    locus_ = std::make_unique<LocusBoundary>(sp.weights().columns(), sp.basis());
    const Xyz white = sp.weights().integrate(sp.basis());
    axes_[0] =
        chroma_axis(locus_->lower().X, locus_->upper().X, res.chroma_steps, white.X / white.sum());
    axes_[1] =
        chroma_axis(locus_->lower().Y, locus_->upper().Y, res.chroma_steps, white.Y / white.sum());
    axes_[2] = {0.0};
    eps_ = 1e-12;
  }
  nx_ = static_cast<int>(axes_[0].size());
  ny_ = static_cast<int>(axes_[1].size());
  nz_ = static_cast<int>(axes_[2].size());
  const std::size_t nodes = static_cast<std::size_t>(nx_) * ny_ * nz_;
  const std::size_t cells = static_cast<std::size_t>(nx_ - 1) * (ny_ - 1) * std::max(nz_ - 1, 1);
  nodes_ = std::vector<std::atomic<const float*>>(nodes);
  cells_ = std::vector<std::atomic<const void*>>(cells);
  for (auto& n : nodes_) n.store(nullptr, std::memory_order_relaxed);
  for (auto& c : cells_) c.store(nullptr, std::memory_order_relaxed);
  solved_.assign(nodes, 0);
}

ExactTable::~ExactTable() = default;

std::string ExactTable::layout() const {
  std::string s = "exact table 1; ";
  if (!reflectance_)
    return s.append("emission chroma 1/")
        .append(std::to_string(res_.chroma_steps))
        .append(" through the basis white");
  s.append("reflectance frame");
  for (double v : frame_) s.append(" ").append(number(v));
  s.append("; steps ").append(std::to_string(res_.steps)).append("/");
  return s.append(std::to_string(res_.coarse_steps));
}

ExactTableStats ExactTable::stats() const {
  ExactTableStats s;
  s.nodes_computed = stats_.computed.load();
  s.nodes_loaded = stats_.loaded.load();
  s.nodes_outside = stats_.outside.load();
  s.nodes_boundary = stats_.boundary.load();
  s.nodes_constructed = stats_.constructed.load();
  s.boundary_cells = stats_.cells.load();
  return s;
}

Xyz ExactTable::node_coords(std::size_t index) const {
  const std::size_t ix = index % nx_, rest = index / nx_;
  return {axes_[0][ix], axes_[1][rest % ny_], axes_[2][rest / ny_]};
}

Xyz ExactTable::node_target(std::size_t index) const {
  const Xyz u = node_coords(index);
  if (reflectance_) return mul(target_from_u_, u);
  return {u.X, u.Y, 1 - u.X - u.Y};
}

double ExactTable::distance(const Xyz& u, std::size_t* facet) const {
  return reflectance_ ? solid_->distance(u, facet) : locus_->distance(u, facet);
}

BoundarySpectrum ExactTable::boundary_spectrum(const Xyz& u) const {
  return reflectance_ ? solid_->spectrum(u) : locus_->spectrum(u);
}

std::vector<double> ExactTable::constructed_spectrum(const Xyz& u) const {
  // The anchor (a grey of the node's luminance, or the white light of X+Y+Z = 1), the
  // boundary point b on the ray from it through the node, and the blend of their exact
  // spectra that lands on the node: exact and within the bounds by convexity.
  std::vector<double> anchor(bands_), out(bands_);
  Xyz a;
  if (reflectance_) {
    const double Y = mul(target_from_u_, u).Y;
    std::fill(anchor.begin(), anchor.end(), Y);
    a = mul(u_from_target_, Y * sp_.weights().unit_white());
  } else {
    const Xyz w = sp_.weights().integrate(sp_.basis());
    for (std::size_t k = 0; k < bands_; ++k) anchor[k] = sp_.basis()[k] / w.sum();
    a = {w.X / w.sum(), w.Y / w.sum(), 0};
  }
  const double s = reflectance_ ? solid_->max_step(a, u) : locus_->max_step(a, u);
  if (!(s >= 1) || !std::isfinite(s)) return anchor;  // the node is the anchor itself
  const BoundarySpectrum edge = boundary_spectrum(a + s * (u - a));
  const double theta = 1 / s;
  for (std::size_t k = 0; k < bands_; ++k) out[k] = (1 - theta) * anchor[k] + theta * edge.value(k);
  return out;
}

float* ExactTable::store(std::span<const double> values) {
  std::lock_guard<std::mutex> lock(arena_mutex_);
  if (arena_.empty() || arena_used_ == kArenaBlockNodes) {
    arena_.emplace_back(kArenaBlockNodes * bands_);
    arena_used_ = 0;
  }
  float* p = arena_.back().data() + bands_ * arena_used_++;
  const float upper = reflectance_ ? 1.0f : INFINITY;
  for (std::size_t k = 0; k < bands_; ++k)
    p[k] = std::clamp(static_cast<float>(values[k]), 0.0f, upper);
  return p;
}

const float* ExactTable::compute_node(std::size_t index) {
  std::lock_guard<std::mutex> lock(locks_[index % locks_.size()]);
  const float* ready = nodes_[index].load(std::memory_order_acquire);
  if (ready) return ready;
  const Xyz u = node_coords(index);
  const double d = distance(u, nullptr);
  const float* result = &kOutsideNode;
  // Relative to the node's coordinates (as the clip's, core/cell_clipping.h): black is on the
  // boundary exactly.
  const double tol = reflectance_ ? eps_ * u.max_abs() : eps_;
  if (d > tol) {
    stats_.outside++;
  } else if (d >= -tol) {
    // On the boundary: the spectrum is (nearly) unique and known in closed form.
    const BoundarySpectrum b = boundary_spectrum(u);
    std::vector<double> v(bands_);
    for (std::size_t k = 0; k < bands_; ++k) v[k] = b.value(k);
    result = store(v);
    stats_.boundary++;
  } else {
    const Xyz t = node_target(index);
    SpectrumResult r = sp_.spectralize_target(t);
    const bool exact = r.status == Outcome::exact && r.relative_error <= 1e-9 &&
                       relative_error(r.target, t) <= 1e-12;
    if (!exact) {
      r.values = constructed_spectrum(u);
      stats_.constructed++;
    }
    result = store(r.values);
    solved_[index] = 1;
    stats_.computed++;
  }
  nodes_[index].store(result, std::memory_order_release);
  return result;
}

inline const float* ExactTable::node(std::size_t index) {
  const float* p = nodes_[index].load(std::memory_order_acquire);
  return p ? p : compute_node(index);
}

const float* ExactTable::node_spectrum(std::size_t index) const {
  const float* p = nodes_[index].load(std::memory_order_acquire);
  return p == &kOutsideNode ? nullptr : p;
}

const void* ExactTable::build_cell(std::size_t index) {
  const std::size_t cx = nx_ - 1, cy = ny_ - 1;
  const std::size_t ix = index % cx, iy = (index / cx) % cy, iz = index / (cx * cy);
  const std::size_t base = ix + nx_ * (iy + ny_ * iz);
  const int corners = reflectance_ ? 8 : 4;
  std::array<std::size_t, 8> corner{};
  bool all_in = true;
  for (int c = 0; c < corners; ++c) {
    corner[c] = base + (c & 1) + ((c >> 1) & 1) * nx_ + ((c >> 2) & 1) * nx_ * ny_;
    all_in = node(corner[c]) != &kOutsideNode && all_in;
  }
  std::lock_guard<std::mutex> lock(cell_locks_[index % cell_locks_.size()]);
  const void* ready = cells_[index].load(std::memory_order_acquire);
  if (ready) return ready;
  const void* result = &kInsideCell;  // convex gamut: a cell with every corner in it is in it
  if (!all_in) {
    const Xyz lower = node_coords(corner[0]), upper = node_coords(corner[corners - 1]);
    const ClippedCell clipped =
        reflectance_ ? clip_box(lower, upper, solid_->cutting(lower, upper, eps_), eps_)
                     : clip_rectangle(lower, upper, locus_->planes(), eps_);
    result = &kOutsideCell;
    if (!clipped.simplices.empty()) {
      // Each cell keeps its own boundary vertices, made from its own clip: the cell is the
      // same whichever thread builds it, when (a table file shares them, core/table_file.h).
      BoundaryCell cell;
      std::vector<std::uint32_t> ref(clipped.vertices.size());
      for (std::size_t v = 0; v < clipped.vertices.size(); ++v) {
        const ClipVertex& cv = clipped.vertices[v];
        if (cv.corner >= 0 && node(corner[cv.corner]) != &kOutsideNode) {
          ref[v] = static_cast<std::uint32_t>(cv.corner);
          continue;
        }
        // A point on the boundary (or a corner within rounding of it but outside).
        ref[v] = kBoundaryVertex | static_cast<std::uint32_t>(cell.vertices.size());
        cell.vertices.push_back({cv.p, boundary_spectrum(cv.p)});
      }
      for (const auto& s : clipped.simplices) {
        const auto& p = clipped.vertices;
        cell.simplices.push_back(
            {{ref[s[0]], ref[s[1]], ref[s[2]], ref[s[3]]},
             barycentric_map(p[s[0]].p, p[s[1]].p, p[s[2]].p, p[s[3]].p, !reflectance_)});
      }
      std::lock_guard<std::mutex> arena(boundary_mutex_);
      boundary_cells_.push_back(std::move(cell));
      result = &boundary_cells_.back();
      stats_.cells++;
    }
  }
  cells_[index].store(result, std::memory_order_release);
  return result;
}

ExactTable::CellKind ExactTable::cell(std::size_t index, const BoundaryCell** data) const {
  const void* p = cells_[index].load(std::memory_order_acquire);
  if (p == &kInsideCell) return CellKind::inside;
  if (p == &kOutsideCell || p == nullptr) return CellKind::outside;
  if (data) *data = static_cast<const BoundaryCell*>(p);
  return CellKind::boundary;
}

int ExactTable::find_interval(int a, double u) const {
  const std::vector<double>& axis = axes_[a];
  if (!(u >= axis.front() && u <= axis.back())) return -1;
  const auto it = std::upper_bound(axis.begin(), axis.end(), u);
  return static_cast<int>(std::min<std::ptrdiff_t>(it - axis.begin() - 1,
                                                   static_cast<std::ptrdiff_t>(axis.size()) - 2));
}

bool ExactTable::locate(const Xyz& target, TableBlend& blend, bool nearest) {
  if (!target.finite()) return false;
  double scale = 1;
  Xyz u;
  if (reflectance_) {
    u = mul(u_from_target_, target);
  } else {
    scale = target.sum();
    if (!(scale > 0)) return false;
    u = {target.X / scale, target.Y / scale, 0};
  }
  const int dims = reflectance_ ? 3 : 2;
  int i[3] = {0, 0, 0};
  double f[3] = {0, 0, 0};
  for (int a = 0; a < dims; ++a) {
    const std::vector<double>& axis = axes_[a];
    double v = u[a];
    if (nearest) v = std::clamp(v, axis.front(), axis.back());
    i[a] = find_interval(a, v);
    if (i[a] < 0) return false;
    f[a] = std::clamp((v - axis[i[a]]) / (axis[i[a] + 1] - axis[i[a]]), 0.0, 1.0);
    u[a] = v;
  }
  if (cell_blend(i, f, u, scale, blend, false)) return true;
  if (!nearest) return false;
  // A point on a face between cells (the solid's white vertex is a corner of cells outside
  // it) belongs to the neighbours that touch it too; else the nearest simplex of its cell.
  for (int c = 1; c < (1 << dims); ++c) {
    int j[3] = {i[0], i[1], i[2]};
    double g[3] = {f[0], f[1], f[2]};
    bool touches = true;
    for (int a = 0; a < dims && touches; ++a) {
      if (!((c >> a) & 1)) continue;
      if (f[a] <= 1e-9 && i[a] > 0)
        --j[a], g[a] = 1;
      else if (f[a] >= 1 - 1e-9 && i[a] + 2 < static_cast<int>(axes_[a].size()))
        ++j[a], g[a] = 0;
      else
        touches = false;
    }
    if (touches && cell_blend(j, g, u, scale, blend, false)) return true;
  }
  return cell_blend(i, f, u, scale, blend, true);
}

bool ExactTable::cell_blend(const int i[3], const double f[3], const Xyz& u, double scale,
                            TableBlend& blend, bool nearest) {
  const int dims = reflectance_ ? 3 : 2;
  const std::size_t cell = i[0] + (nx_ - 1) * (i[1] + (ny_ - 1) * static_cast<std::size_t>(i[2]));
  const void* state = cells_[cell].load(std::memory_order_acquire);
  if (!state) state = build_cell(cell);
  if (state == &kOutsideCell) return false;
  blend = TableBlend{};
  if (state == &kInsideCell) {
    const std::size_t base = i[0] + nx_ * (i[1] + ny_ * static_cast<std::size_t>(i[2]));
    const std::size_t stride[3] = {1, static_cast<std::size_t>(nx_),
                                   static_cast<std::size_t>(nx_) * ny_};
    // Kuhn's simplices: walk from the lower corner along the axes in decreasing order of the
    // fractional coordinates; the weights are the gaps between them (exact linear
    // interpolation on the simplex holding the point).
    // A sorting network of 2 or 3 axes (std::sort's introsort here drew GCC 16's
    // -Warray-bounds: it cannot see that the range holds at most 3).
    int order[3] = {0, 1, 2};
    auto in_order = [&](int& a, int& b) {
      if (f[b] > f[a]) std::swap(a, b);
    };
    in_order(order[0], order[1]);
    if (dims == 3) {
      in_order(order[1], order[2]);
      in_order(order[0], order[1]);
    }
    std::size_t n = base;
    double prev = 1;
    for (int k = 0; k <= dims; ++k) {
      const double fk = k < dims ? f[order[k]] : 0.0;
      blend.dense[k] = nodes_[n].load(std::memory_order_acquire);
      blend.weight[k] = static_cast<float>((prev - fk) * scale);
      prev = fk;
      if (k < dims) n += stride[order[k]];
    }
    blend.count = dims + 1;
    return true;
  }
  const auto* data = static_cast<const BoundaryCell*>(state);
  double best = -INFINITY, best_w[4] = {0, 0, 0, 0};
  const Simplex* chosen = nullptr;
  for (const Simplex& s : data->simplices) {
    const auto& m = s.map;
    const Xyz d = u - Xyz{m[9], m[10], m[11]};
    double w[4];
    w[1] = m[0] * d.X + m[1] * d.Y + m[2] * d.Z;
    w[2] = m[3] * d.X + m[4] * d.Y + m[5] * d.Z;
    w[3] = reflectance_ ? m[6] * d.X + m[7] * d.Y + m[8] * d.Z : 0.0;
    w[0] = 1 - w[1] - w[2] - w[3];
    const double worst = std::min({w[0], w[1], w[2], reflectance_ ? w[3] : 1.0});
    if (worst > best) {
      best = worst, chosen = &s;
      std::copy(w, w + 4, best_w);
      if (worst >= -kInsideWeight) break;
    }
  }
  if (!chosen) return false;
  if (best < -kOutsideWeight) {
    if (!nearest) return false;
    // Within rounding of the gamut but outside the cell's simplices (float input on the
    // boundary): the blend of the nearest point of the nearest simplex.
    const std::size_t base = i[0] + nx_ * (i[1] + ny_ * static_cast<std::size_t>(i[2]));
    const Xyz lo = node_coords(base);
    const Xyz hi = node_coords(base + 1 + nx_ + (reflectance_ ? nx_ * ny_ : 0));
    double nearest_dist = INFINITY;
    for (const Simplex& s : data->simplices) {
      double p[4][3], w[4];
      for (int v = 0; v < 4; ++v) {
        const std::uint32_t r = s.vertex[v];
        const Xyz q = (r & kBoundaryVertex)
                          ? data->vertices[r & ~kBoundaryVertex].position
                          : Xyz{r & 1 ? hi.X : lo.X, r & 2 ? hi.Y : lo.Y, r & 4 ? hi.Z : lo.Z};
        p[v][0] = q.X, p[v][1] = q.Y, p[v][2] = reflectance_ ? q.Z : 0.0;
      }
      const double x[3] = {u.X, u.Y, reflectance_ ? u.Z : 0.0};
      const double dist = spz::detail::closest_in_simplex(p, reflectance_ ? 3 : 2, x, w);
      if (dist < nearest_dist) {
        nearest_dist = dist, chosen = &s;
        std::copy(w, w + 4, best_w);
      }
    }
  }
  double sum = 0;
  for (double& w : best_w) sum += (w = std::max(w, 0.0));
  const int count = reflectance_ ? 4 : 3;
  const std::size_t base = i[0] + nx_ * (i[1] + ny_ * static_cast<std::size_t>(i[2]));
  for (int k = 0; k < count; ++k) {
    const std::uint32_t v = chosen->vertex[k];
    if (v & kBoundaryVertex) {
      blend.boundary[k] = &data->vertices[v & ~kBoundaryVertex].spectrum;
    } else {
      const std::size_t n = base + (v & 1) + ((v >> 1) & 1) * nx_ + ((v >> 2) & 1) * nx_ * ny_;
      blend.dense[k] = nodes_[n].load(std::memory_order_acquire);
    }
    blend.weight[k] = static_cast<float>(best_w[k] / sum * scale);
  }
  blend.count = count;
  return true;
}

void ExactTable::blend_into(const TableBlend& b, float* out) const {
  const std::size_t n = bands_;
  bool dense = true;
  for (int k = 0; k < b.count; ++k) dense = dense && b.dense[k];
  float* __restrict o = out;
  if (dense && b.count == 4) {
    const float* __restrict p0 = b.dense[0], * __restrict p1 = b.dense[1], * __restrict p2 = b.dense[2], * __restrict p3 = b.dense[3];
    const float w0 = b.weight[0], w1 = b.weight[1], w2 = b.weight[2], w3 = b.weight[3];
    for (std::size_t i = 0; i < n; ++i) o[i] = w0 * p0[i] + w1 * p1[i] + w2 * p2[i] + w3 * p3[i];
  } else if (dense && b.count == 3) {
    const float* __restrict p0 = b.dense[0], * __restrict p1 = b.dense[1], * __restrict p2 = b.dense[2];
    const float w0 = b.weight[0], w1 = b.weight[1], w2 = b.weight[2];
    for (std::size_t i = 0; i < n; ++i) o[i] = w0 * p0[i] + w1 * p1[i] + w2 * p2[i];
  } else {
    std::fill(o, o + n, 0.0f);
    for (int k = 0; k < b.count; ++k) {
      const float w = b.weight[k];
      if (b.dense[k]) {
        const float* __restrict p = b.dense[k];
        for (std::size_t i = 0; i < n; ++i) o[i] += w * p[i];
      } else {
        const BoundarySpectrum& s = *b.boundary[k];
        for (std::size_t i = 0; i < n; ++i)
          if ((s.mask[i / 32] >> (i % 32)) & 1u) o[i] += w;
        // The two samples with their own values replace the mask's.
        o[s.i] += w * static_cast<float>(s.a) - (((s.mask[s.i / 32] >> (s.i % 32)) & 1u) ? w : 0);
        if (s.j != s.i)
          o[s.j] += w * static_cast<float>(s.b) - (((s.mask[s.j / 32] >> (s.j % 32)) & 1u) ? w : 0);
      }
    }
  }
  if (reflectance_)
    for (std::size_t i = 0; i < n; ++i) o[i] = std::min(o[i], 1.0f);
}

void ExactTable::build(const ParallelFor& parallel) {
  auto run = [&](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    if (parallel)
      parallel(n, body);
    else
      body(0, n);
  };
  run(nodes_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) node(i);
  });
  run(cells_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (!cells_[i].load(std::memory_order_acquire)) build_cell(i);
  });
}

void ExactTable::for_each_solved_node(
    const std::function<void(std::size_t, std::span<const float>)>& fn) const {
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const float* p = nodes_[i].load(std::memory_order_acquire);
    if (p && p != &kOutsideNode && solved_[i]) fn(i, std::span<const float>(p, bands_));
  }
}

bool ExactTable::adopt_node(std::size_t index, std::span<const float> values) {
  if (index >= nodes_.size() || values.size() != bands_) return false;
  if (nodes_[index].load(std::memory_order_acquire)) return true;  // already known here
  // Only nodes strictly inside are solved (and stored): one elsewhere is not ours.
  const Xyz u = node_coords(index);
  if (!(distance(u, nullptr) < -(reflectance_ ? eps_ * u.max_abs() : eps_))) return false;
  const double upper = reflectance_ ? 1.0 : INFINITY;
  Xyz xyz;
  std::vector<double> v(bands_);
  for (std::size_t i = 0; i < bands_; ++i) {
    if (!(values[i] >= 0 && values[i] <= upper)) return false;
    v[i] = values[i];
    xyz = xyz + v[i] * sp_.weights().columns()[i];
  }
  // The node must be the spectrum of its own colour: a file with the right key and checksum
  // can still hold wrong spectra (poisoned, or a bug of another version).
  if (!(relative_error(xyz, node_target(index)) <= kStoredNodeTolerance)) return false;
  std::lock_guard<std::mutex> lock(locks_[index % locks_.size()]);
  if (nodes_[index].load(std::memory_order_acquire)) return true;
  const float* stored = store(v);
  solved_[index] = 1;
  stats_.loaded++;
  nodes_[index].store(stored, std::memory_order_release);
  return true;
}

}  // namespace spectralize
