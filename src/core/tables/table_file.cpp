#include "core/tables/table_file.h"

#include <spectralize/rt_format.h>
#include <spectralize/rt.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <tuple>
#include <vector>

#include "spectralize/core/error.h"
#include "spectralize/version.h"

namespace spectralize {

namespace {

static_assert(sizeof(spz_file_header) == SPZ_HEADER_SIZE, "the header is 1024 bytes");
// The file is little-endian: the native layout is written as is.
static_assert(std::endian::native == std::endian::little, "little-endian hosts only");
static_assert(offsetof(spz_file_header, sections) == 432, "header layout");
static_assert(offsetof(spz_file_header, sample_bound) == 704, "header layout");
static_assert(offsetof(spz_file_header, colorspace) == 720, "header layout");
// The reader's checksum skips bytes 24..31: the checksum field.
static_assert(offsetof(spz_file_header, checksum) == 24 && sizeof(spz_file_header::checksum) == 8,
              "header layout");

void copy_name(char* field, std::size_t size, const std::string& value, const char* what) {
  if (value.size() >= size)
    throw Error(std::string(what) + " " + quote(value) + " is too long for a table (at most " +
                std::to_string(size - 1) + " bytes)");
  std::memset(field, 0, size);
  std::memcpy(field, value.data(), value.size());
}

// The lookup of an axis (spz_axis_bin): bins of half the shortest interval from the first
// position; per bin the interior nodes of lower bins and the one inside it, binned by the
// evaluator's own float arithmetic (spz::detail::axis_bin), which its loader checks.
struct AxisLookup {
  std::vector<spz_axis_bin> bins;
  float origin = 0, inverse_bin = 1;
};

AxisLookup lookup_of(const std::vector<float>& axis, const float* inverse, std::uint32_t stride) {
  AxisLookup l;
  l.origin = axis.front();
  if (axis.size() < 2) {
    l.bins = {{0, INFINITY, axis.front(), 0.0f}};
    return l;
  }
  float shortest = INFINITY;
  for (std::size_t k = 0; k + 1 < axis.size(); ++k)
    shortest = std::min(shortest, axis[k + 1] - axis[k]);
  l.inverse_bin = 2 / shortest;
  const std::size_t size =
      static_cast<std::size_t>(std::ceil((axis.back() - axis.front()) * l.inverse_bin)) + 1;
  l.bins.assign(size, {0, INFINITY, axis[0], inverse ? inverse[0] : 0.0f});
  const float last = static_cast<float>(size - 1);
  for (std::size_t j = 1; j + 1 < axis.size(); ++j) {
    const std::uint32_t b = spz::detail::axis_bin(axis[j], l.origin, l.inverse_bin, last);
    if (l.bins[b].split != INFINITY)
      throw Error("table file: two nodes of an axis fall in one lookup bin");
    l.bins[b].split = axis[j];
    for (std::size_t c = b + 1; c < size; ++c)
      l.bins[c] = {static_cast<std::uint32_t>(j) * stride, INFINITY, axis[j],
                   inverse ? inverse[j] : 0.0f};
  }
  return l;
}

}  // namespace

std::string encode_table_file(const ExactTable& table, const Spectralizer& sp,
                              const TableFileInfo& info) {
  const SpectralizerSettings& s = sp.settings();
  const bool reflectance = table.reflectance();
  const std::size_t bands = table.bands();
  const std::uint32_t words = static_cast<std::uint32_t>((bands + 31) / 32);
  spz_file_header h;
  std::memset(&h, 0, sizeof h);
  std::memcpy(h.magic, "SPZTABLE", 8);
  h.version = SPZ_FORMAT_VERSION;
  h.byte_order = SPZ_BYTE_ORDER_MARK;
  h.header_size = SPZ_HEADER_SIZE;
  h.mode = reflectance ? SPZ_MODE_REFLECTANCE : SPZ_MODE_EMISSION;
  h.bands = static_cast<std::uint32_t>(bands);
  h.mask_words = words;
  h.lambda_start = s.grid.start();
  h.lambda_step = s.grid.step();
  std::copy(table.frame().begin(), table.frame().end(), h.rgb_to_xyz);
  std::copy(table.target_from_rgb().begin(), table.target_from_rgb().end(), h.rgb_to_target);
  std::copy(table.rgb_from_target().begin(), table.rgb_from_target().end(), h.target_to_rgb);
  const Xyz lw = sp.mapping_white(), sw = sp.weights().unit_white();
  for (int k = 0; k < 3; ++k) h.locus_white[k] = lw[k], h.solid_white[k] = sw[k];
  h.locus_margin = kLocusMargin;
  h.solid_margin = kSolidMargin;
  h.snap_tolerance = kSnapTolerance;
  h.locus_scale = sp.locus().scale();
  h.solid_scale = reflectance ? sp.gamut().scale() : 0;
  h.section_count = SPZ_SECTION_COUNT;
  const TableResolution res = table.resolution();
  h.resolution[0] = static_cast<std::uint32_t>(res.steps);
  h.resolution[1] = static_cast<std::uint32_t>(res.coarse_steps);
  h.resolution[2] = static_cast<std::uint32_t>(res.chroma_steps);
  copy_name(h.colorspace, sizeof h.colorspace, info.colorspace, "colour space");
  copy_name(h.interop_id, sizeof h.interop_id, info.interop_id, "interop ID");
  copy_name(h.model, sizeof h.model, std::string(s.model.name()), "model");
  copy_name(h.observer, sizeof h.observer, s.observer, "observer");
  copy_name(h.illuminant, sizeof h.illuminant, reflectance ? s.illuminant : "", "illuminant");
  copy_name(h.emission_basis, sizeof h.emission_basis, reflectance ? "" : s.emission_basis,
            "emission basis");
  copy_name(h.generator, sizeof h.generator, "spectralize " SPECTRALIZE_VERSION, "generator");

  // The sections' contents.
  std::vector<float> axes[3], inverse;
  std::vector<spz_axis_bin> luts;
  const int dims = reflectance ? 3 : 2;
  const std::size_t nx = table.axis(0).size(), ny = table.axis(1).size();
  if (table.node_count() * bands >= SPZ_BOUNDARY_BIT)
    throw Error("table file: more than 2^31 samples of node spectra");
  // Node strides (rt_format.h): offsets that add up to a node's index, in 32 bits.
  const std::uint32_t stride[3] = {1, static_cast<std::uint32_t>(nx),
                                   static_cast<std::uint32_t>(nx * ny)};
  for (int a = 0; a < 3; ++a) {
    for (double v : table.axis(a)) axes[a].push_back(static_cast<float>(v));
    h.nodes[a] = static_cast<std::uint32_t>(axes[a].size());
    const std::size_t first_inverse = inverse.size();
    if (a < dims)
      for (std::size_t k = 0; k + 1 < axes[a].size(); ++k)
        inverse.push_back(static_cast<float>(1.0 / (table.axis(a)[k + 1] - table.axis(a)[k])));
    const bool has_inverse = a < dims && axes[a].size() > 1;
    const AxisLookup l =
        lookup_of(axes[a], has_inverse ? &inverse[first_inverse] : nullptr, stride[a]);
    h.lut_size[a] = static_cast<std::uint32_t>(l.bins.size());
    h.lut_origin[a] = l.origin;
    h.lut_inverse_bin[a] = l.inverse_bin;
    luts.insert(luts.end(), l.bins.begin(), l.bins.end());
  }
  luts.push_back(spz_axis_bin{});  // read as "the next bin" by the last bin of the last axis
  std::vector<std::uint32_t> slots(table.node_count(), SPZ_OUTSIDE);
  std::vector<float> spectra;
  std::uint32_t next = 0;
  for (std::size_t n = 0; n < table.node_count(); ++n)
    if (const float* p = table.node_spectrum(n)) {
      slots[n] = next++ * static_cast<std::uint32_t>(bands);  // the spectrum's offset
      spectra.insert(spectra.end(), p, p + bands);
    }
  // Boundary vertices: cells that meet at a point made it once each; it is stored once (the
  // first in cell order: the bytes do not depend on which thread built what).
  std::vector<double> positions;
  std::vector<std::uint32_t> masks, picks;
  std::vector<float> values;
  struct Key {
    long long x, y, z;
    bool operator<(const Key& o) const { return std::tie(x, y, z) < std::tie(o.x, o.y, o.z); }
  };
  std::map<Key, std::uint32_t> shared;
  auto vertex_id = [&](const ExactTable::BoundaryVertex& v) {
    const Key key{std::llround(v.position.X * 1e11), std::llround(v.position.Y * 1e11),
                  std::llround(v.position.Z * 1e11)};
    const auto [it, fresh] = shared.emplace(key, static_cast<std::uint32_t>(picks.size()));
    if (fresh) {
      positions.insert(positions.end(), {v.position.X, v.position.Y, v.position.Z});
      masks.insert(masks.end(), v.spectrum.mask.begin(), v.spectrum.mask.end());
      picks.push_back(v.spectrum.i | (v.spectrum.j << 16));
      values.push_back(static_cast<float>(v.spectrum.a));
      values.push_back(static_cast<float>(v.spectrum.b));
    }
    return it->second;
  };
  // Cell codes by each cell's lowest node (rt_format.h): a fetch indexes cells and nodes with
  // one offset; an axis' last node has no cell.
  std::vector<std::uint32_t> cells(table.node_count(), SPZ_OUTSIDE), bcells, simplices;
  std::uint32_t most_simplices = 0;
  for (std::size_t c = 0; c < table.cell_count(); ++c) {
    const ExactTable::BoundaryCell* data = nullptr;
    const std::size_t x = c % (nx - 1), y = (c / (nx - 1)) % (ny - 1),
                      z = c / ((nx - 1) * (ny - 1));
    std::uint32_t& code = cells[x + nx * (y + ny * z)];
    switch (table.cell(c, &data)) {
      case ExactTable::CellKind::inside:
        code = 0;
        break;
      case ExactTable::CellKind::outside:
        code = SPZ_OUTSIDE;
        break;
      case ExactTable::CellKind::boundary:
        code = SPZ_BOUNDARY_BIT | static_cast<std::uint32_t>(bcells.size() / 2);
        bcells.push_back(static_cast<std::uint32_t>(simplices.size() / 4));
        bcells.push_back(static_cast<std::uint32_t>(data->simplices.size()));
        most_simplices =
            std::max(most_simplices, static_cast<std::uint32_t>(data->simplices.size()));
        for (const ExactTable::Simplex& sx : data->simplices)
          for (std::uint32_t r : sx.vertex)
            simplices.push_back(r & SPZ_BOUNDARY_BIT
                                    ? SPZ_BOUNDARY_BIT |
                                          vertex_id(data->vertices[r & ~SPZ_BOUNDARY_BIT])
                                    : r);
        break;
    }
  }
  auto planes_of = [](const ConvexGamut& g) {
    std::vector<double> out;
    for (std::size_t f = 0; f < g.facets(); ++f) {
      const Xyz n = g.normal(f);
      out.insert(out.end(), {n.X, n.Y, n.Z, g.offset(f)});
    }
    return out;
  };
  // What a reader checks the table's meaning with (rt_format.h, since version 3): each band's
  // target X, Y, Z per unit sample, the largest sample, the most simplices a fetch tests.
  std::vector<double> band_weights;
  for (const Xyz& w : sp.weights().columns())
    band_weights.insert(band_weights.end(), {w.X, w.Y, w.Z});
  double largest = 0;
  for (float v : spectra) largest = std::max(largest, static_cast<double>(v));
  for (float v : values) largest = std::max(largest, static_cast<double>(v));
  for (std::uint32_t m : masks)
    if (m != 0) largest = std::max(largest, 1.0);
  h.sample_bound = largest > 0 ? largest : 1;
  h.max_cell_simplices = most_simplices;
  if (most_simplices > SPZ_MAX_CELL_SIMPLICES)
    throw Error("a boundary cell of the table has " + std::to_string(most_simplices) +
                " simplices, more than a table may hold (" +
                std::to_string(SPZ_MAX_CELL_SIMPLICES) + "): use a coarser --wavelengths");
  const std::vector<double> locus = planes_of(sp.locus());
  const std::vector<double> solid = reflectance ? planes_of(sp.gamut()) : std::vector<double>{};

  // Layout: header, then each section at the next multiple of 64.
  struct Part {
    const void* data;
    std::size_t count, element;
  };
  const Part parts[SPZ_SECTION_COUNT] = {{axes[0].data(), axes[0].size(), 4},
                                         {axes[1].data(), axes[1].size(), 4},
                                         {axes[2].data(), axes[2].size(), 4},
                                         {inverse.data(), inverse.size(), 4},
                                         {luts.data(), luts.size(), sizeof(spz_axis_bin)},
                                         {cells.data(), cells.size(), 4},
                                         {slots.data(), slots.size(), 4},
                                         {spectra.data(), spectra.size(), 4},
                                         {bcells.data(), bcells.size(), 4},
                                         {simplices.data(), simplices.size(), 4},
                                         {positions.data(), positions.size(), 8},
                                         {masks.data(), masks.size(), 4},
                                         {picks.data(), picks.size(), 4},
                                         {values.data(), values.size(), 4},
                                         {locus.data(), locus.size(), 8},
                                         {solid.data(), solid.size(), 8},
                                         {band_weights.data(), band_weights.size(), 8}};
  std::size_t at = SPZ_HEADER_SIZE;
  for (int k = 0; k < static_cast<int>(SPZ_SECTION_COUNT); ++k) {
    at = (at + SPZ_SECTION_ALIGNMENT - 1) / SPZ_SECTION_ALIGNMENT * SPZ_SECTION_ALIGNMENT;
    h.sections[k] = {parts[k].count ? at : 0, parts[k].count};
    at += parts[k].count * parts[k].element;
  }
  h.file_size = at;
  std::string bytes(at, '\0');
  for (int k = 0; k < static_cast<int>(SPZ_SECTION_COUNT); ++k)
    if (parts[k].count)
      std::memcpy(bytes.data() + h.sections[k].offset, parts[k].data,
                  parts[k].count * parts[k].element);
  std::memcpy(bytes.data(), &h, sizeof h);
  // The checksum over everything, its own field as zeros: the reader's own function
  // (spectralize/rt.hpp), so that what is written is what is checked.
  h.checksum = spz::detail::table_checksum(reinterpret_cast<const unsigned char*>(bytes.data()),
                                           bytes.size());
  std::memcpy(bytes.data() + offsetof(spz_file_header, checksum), &h.checksum, 8);
  return bytes;
}

}  // namespace spectralize
