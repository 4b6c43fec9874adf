// The render-time table file (src/core/tables/table_file.h, docs/DESIGN.md §14; the layout of
// include/spectralize/rt_format.h): what encode_table_file writes for a table built whole.
// The header says what the table was made from; the sections lie where the format puts them
// with the counts the table implies; the checksum is FNV-1a 64 of the file with its own field
// zero (computed here); the bytes do not depend on the threads; the reader
// (include/spectralize/rt.hpp) accepts them and its spectra reproduce every colour they are
// fetched for (the test's own integration, test_support.h) within the bounds, boundary vertices
// included; names too long for the header are refused naming them. How the reader refuses
// truncated, flipped, re-versioned or otherwise bad files, naming the file, is rt_test.cpp's
// (RtFile, on the tables `spectralize table` writes).

#include "core/tables/table_file.h"

#include <gtest/gtest.h>

#include <spectralize/rt_format.h>
// The one unit of unit_tests that compiles the evaluator's definitions
// (include/spectralize/rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "core/tables/exact_table.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::frame_of;

// A coarse table (fast to build): the file's contract does not depend on the spacing.
const TableResolution kCoarse{6, 2, 24};
// Coarser still for the shared tables of the tests after it.
const TableResolution kCoarser{4, 1, 16};

ParallelFor threads(int n) {
  return [n](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < n; ++t)
      pool.emplace_back([&] {
        for (std::size_t b; (b = next.fetch_add(37)) < count;) body(b, std::min(count, b + 37));
      });
    for (auto& t : pool) t.join();
  };
}

TEST(TableFile, TheFileIsTheSameWhateverTheThreadsAndAgreesWithTheCore) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  ExactTable one(sp, frame_of(test::kRec709ToXyz), kCoarse),
      two(sp, frame_of(test::kRec709ToXyz), kCoarse);
  one.build(threads(1));
  two.build(threads(3));
  const std::string a = encode_table_file(one, sp, {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  const std::string b = encode_table_file(two, sp, {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  EXPECT_EQ(a, b);
  // The evaluator reads it, and gives the core's spectra.
  std::vector<std::uint64_t> aligned(a.size() / 8 + 1);
  std::memcpy(aligned.data(), a.data(), a.size());
  spz::TableView view;
  char error[256];
  ASSERT_TRUE(view.open(aligned.data(), a.size(), error, sizeof error)) << error;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  std::vector<float> core(81), rt(81);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const float rgb[3] = {u(rng), u(rng), u(rng)};
    spz::Spectrum spec;
    if (view.fetch(rgb, spec) != SPZ_EXACT) continue;
    spz::samples(spec, rt.data());
    TableBlend blend;
    ASSERT_TRUE(one.locate(mul(one.target_from_rgb(), Xyz{rgb[0], rgb[1], rgb[2]}), blend, true));
    one.blend_into(blend, core.data());
    for (int i = 0; i < 81; ++i) worst = std::max(worst, double(std::abs(core[i] - rt[i])));
  }
  EXPECT_LE(worst, 1e-6);
}

// The file's bytes, 8-byte aligned (as the reader requires) and opened.
struct Opened {
  std::vector<std::uint64_t> aligned;
  spz::TableView view;
  spz_file_header h;
  explicit Opened(const std::string& bytes) : aligned(bytes.size() / 8 + 1) {
    std::memcpy(aligned.data(), bytes.data(), bytes.size());
    std::memcpy(&h, bytes.data(), sizeof h);
    char error[256] = "";
    EXPECT_TRUE(view.open(aligned.data(), bytes.size(), error, sizeof error)) << error;
  }
  template <typename T>
  const T* section(int k) const {
    return reinterpret_cast<const T*>(reinterpret_cast<const char*>(aligned.data()) +
                                      h.sections[k].offset);
  }
};

// FNV-1a 64 as published (offset basis 0xcbf29ce484222325, prime 1099511628211) over the
// file, the checksum field (bytes 24..31) taken as zero: the format's definition (rt_format.h),
// written out here, so that a reader written from the format accepts the file.
std::uint64_t fnv1a_with_checksum_zeroed(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    const unsigned char c = (k >= 24 && k < 32) ? 0 : static_cast<unsigned char>(bytes[k]);
    h = (h ^ c) * 1099511628211ull;
  }
  return h;
}

// One table per mode, built whole, and its file.
struct Made {
  Spectralizer sp;
  ExactTable table;
  std::string bytes;
  Made(const SpectralizerSettings& s, const TableFileInfo& info)
      : sp(s), table(sp, frame_of(test::kRec709ToXyz), kCoarser) {
    table.build();
    bytes = encode_table_file(table, sp, info);
  }
};

SpectralizerSettings settings_of(Mode mode);

// The tables of the tests below, built once (a whole table takes about a second here).
const Made& made(Mode mode) {
  static const Made reflectance(settings_of(Mode::reflectance),
                                {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  static const Made emission(settings_of(Mode::emission),
                             {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  return mode == Mode::reflectance ? reflectance : emission;
}

SpectralizerSettings settings_of(Mode mode) {
  SpectralizerSettings s;
  s.mode = mode;
  if (mode == Mode::reflectance) {
    s.observer = "cie1964";
    s.illuminant = "D50";
    s.model = "natural";
  }
  return s;
}

std::string field(const char* text, std::size_t size) {
  return std::string(text, strnlen(text, size));
}

TEST(TableFile, TheHeaderSaysWhatTheTableWasMadeFrom) {
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const bool refl = mode == Mode::reflectance;
    const Made& m = made(mode);
    const spz_file_header& h = Opened(m.bytes).h;
    EXPECT_EQ(std::string(h.magic, 8), "SPZTABLE");
    EXPECT_EQ(h.version, 4u);  // rt_format.h: version 4, with the band weights and bins' nodes
    EXPECT_EQ(h.byte_order, 0x01020304u);
    EXPECT_EQ(std::memcmp(m.bytes.data() + 12, "\x04\x03\x02\x01", 4), 0);  // little-endian
    EXPECT_EQ(h.header_size, 1024u);
    EXPECT_EQ(h.file_size, m.bytes.size());
    EXPECT_EQ(h.mode, refl ? 1u : 0u);
    EXPECT_EQ(h.bands, 81u);
    EXPECT_EQ(h.mask_words, 3u);  // 81 samples: 3 words of 32 bits
    EXPECT_EQ(h.lambda_start, 380.0);
    EXPECT_EQ(h.lambda_step, 5.0);
    EXPECT_EQ(field(h.colorspace, sizeof h.colorspace), "Linear Rec.709 (sRGB)");
    EXPECT_EQ(field(h.interop_id, sizeof h.interop_id), "lin_rec709_scene");
    EXPECT_EQ(field(h.model, sizeof h.model), refl ? "natural" : "exemplar");
    EXPECT_EQ(field(h.observer, sizeof h.observer), refl ? "cie1964" : "cie1931");
    EXPECT_EQ(field(h.illuminant, sizeof h.illuminant), refl ? "D50" : "");
    EXPECT_EQ(field(h.emission_basis, sizeof h.emission_basis), refl ? "" : "flat");
    EXPECT_EQ(field(h.generator, sizeof h.generator).rfind("spectralize ", 0), 0u);
    // The frame is the space's matrix (its white snapped to D65: 1e-9), and the target maps
    // are each other's inverse (1e-12).
    for (int k = 0; k < 9; ++k) {
      EXPECT_NEAR(h.rgb_to_xyz[k], test::kRec709ToXyz[k / 3][k % 3], 1e-9) << k;
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        double p = 0;
        for (int k = 0; k < 3; ++k) p += h.rgb_to_target[3 * r + k] * h.target_to_rgb[3 * k + c];
        EXPECT_NEAR(p, r == c ? 1.0 : 0.0, 1e-12);
      }
    // The mapping's constants (docs/DESIGN.md §5) and, for reflectances, rho == 1 has Y = 1
    // (docs/DESIGN.md §3).
    EXPECT_EQ(h.locus_margin, 1e-6);
    EXPECT_EQ(h.solid_margin, 1e-4);
    EXPECT_EQ(h.snap_tolerance, 1e-6);
    if (refl) {
      EXPECT_NEAR(h.solid_white[1], 1.0, 1e-12);
    }
    EXPECT_EQ(h.resolution[0], 4u);
    EXPECT_EQ(h.resolution[1], 1u);
    EXPECT_EQ(h.resolution[2], 16u);
    EXPECT_EQ(h.section_count, 17u);
    if (!refl) {
      EXPECT_EQ(h.nodes[2], 1u);  // emission: a 2-D grid
    }
    // The checksum is the format's, computed here.
    EXPECT_EQ(h.checksum, fnv1a_with_checksum_zeroed(m.bytes));
  }
}

// The axis lookup (rt_format.h, spz_axis_bin): for every position of an axis' range — each
// node, the floats either side of it, and a fine sweep — the bin's interval plus (v >= split) is
// the interval the sorted positions say (oracle: std::upper_bound), in one step.
TEST(TableFile, EveryPositionFindsItsIntervalInOneStepOfTheLookup) {
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Made& m = made(mode);
    const Opened o(m.bytes);
    const spz_file_header& h = o.h;
    const spz_axis_bin* bins = o.section<spz_axis_bin>(SPZ_SECTION_AXIS_LUT);
    const int dims = mode == Mode::reflectance ? 3 : 2;
    const float* inverses = o.section<float>(SPZ_SECTION_AXIS_INVERSE);
    const std::uint32_t stride[3] = {1, h.nodes[0], h.nodes[0] * h.nodes[1]};
    for (int a = 0; a < dims; ++a) {
      const float* p = o.section<float>(SPZ_SECTION_AXIS_X + a);
      const std::uint32_t n = h.nodes[a];
      const float* inverse = inverses;
      inverses += n - 1;
      std::vector<float> probes;
      for (std::uint32_t k = 0; k < n; ++k)
        probes.insert(probes.end(),
                      {std::nextafter(p[k], -INFINITY), p[k], std::nextafter(p[k], INFINITY)});
      for (int i = 0; i <= 10000; ++i) probes.push_back(p[0] + (p[n - 1] - p[0]) * (i / 1e4f));
      int checked = 0;
      for (const float v : probes) {
        if (!(v >= p[0] && v <= p[n - 1])) continue;
        const std::uint32_t want = std::min<std::uint32_t>(
            static_cast<std::uint32_t>(std::upper_bound(p, p + n, v) - p) - 1, n - 2);
        float b = (v - h.lut_origin[a]) * h.lut_inverse_bin[a];
        b = std::min(std::max(b, 0.0f), static_cast<float>(h.lut_size[a] - 1));
        const spz_axis_bin& e = bins[static_cast<std::uint32_t>(b)];
        // Past the split the next bin holds the interval: its lowest node's offset (the
        // interval times the axis' node stride), start and inverse length.
        const spz_axis_bin& used = v >= e.split ? (&e)[1] : e;
        EXPECT_EQ(used.node, want * stride[a]) << "axis " << a << " at " << v;
        EXPECT_EQ(used.position, p[want]) << "axis " << a << " at " << v;
        EXPECT_EQ(used.inverse, inverse[want]) << "axis " << a << " at " << v;
        ++checked;
      }
      EXPECT_GT(checked, 10000);
      bins += h.lut_size[a];
    }
  }
}

TEST(TableFile, SectionsLieOnTheirAlignmentWithTheCountsTheTableImplies) {
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const bool refl = mode == Mode::reflectance;
    const Made& m = made(mode);
    const Opened o(m.bytes);
    const spz_file_header& h = o.h;
    // In order after the header, each at a multiple of 64, none overlapping, the last ending
    // the file; an empty section has offset 0. Element sizes from rt_format.h.
    auto element = [](int k) {
      if (k == SPZ_SECTION_AXIS_LUT) return 16u;
      return k == SPZ_SECTION_BOUNDARY_POSITIONS || k == SPZ_SECTION_LOCUS_PLANES ||
                     k == SPZ_SECTION_SOLID_PLANES || k == SPZ_SECTION_BAND_WEIGHTS
                 ? 8u
                 : 4u;
    };
    std::uint64_t end = 1024;
    for (int k = 0; k < 17; ++k) {
      const spz_section_entry& e = h.sections[k];
      if (e.count == 0) {
        EXPECT_EQ(e.offset, 0u) << k;
        continue;
      }
      EXPECT_EQ(e.offset % 64, 0u) << k;
      EXPECT_GE(e.offset, end) << k;
      EXPECT_LT(e.offset, end + 64) << k;  // no gap beyond the alignment
      end = e.offset + e.count * element(k);
    }
    EXPECT_EQ(end, h.file_size);
    // Counts.
    const std::uint64_t nodes = std::uint64_t(h.nodes[0]) * h.nodes[1] * h.nodes[2];
    EXPECT_EQ(nodes, m.table.node_count());
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(h.sections[a].count, m.table.axis(a).size());
      EXPECT_EQ(h.nodes[a], m.table.axis(a).size());
    }
    EXPECT_EQ(h.sections[SPZ_SECTION_AXIS_INVERSE].count,
              h.nodes[0] - 1 + h.nodes[1] - 1 + (refl ? h.nodes[2] - 1 : 0));
    EXPECT_EQ(h.sections[SPZ_SECTION_NODE_SLOTS].count, nodes);
    EXPECT_EQ(h.sections[SPZ_SECTION_CELLS].count, nodes);  // by each cell's lowest node
    // Each cell's code at its lowest node; an axis' last node has none.
    const std::uint32_t* codes = o.section<std::uint32_t>(SPZ_SECTION_CELLS);
    const std::size_t nx = h.nodes[0], ny = h.nodes[1], nz = h.nodes[2];
    std::size_t cell = 0, boundary_seen = 0;
    for (std::size_t z = 0; z < nz; ++z)
      for (std::size_t y = 0; y < ny; ++y)
        for (std::size_t x = 0; x < nx; ++x) {
          const std::uint32_t code = codes[x + nx * (y + ny * z)];
          if (x + 1 == nx || y + 1 == ny || (refl && z + 1 == nz)) {
            EXPECT_EQ(code, SPZ_OUTSIDE) << x << " " << y << " " << z;
            continue;
          }
          switch (m.table.cell(cell++, nullptr)) {
            case ExactTable::CellKind::inside:
              EXPECT_EQ(code, 0u);
              break;
            case ExactTable::CellKind::outside:
              EXPECT_EQ(code, SPZ_OUTSIDE);
              break;
            case ExactTable::CellKind::boundary:
              EXPECT_EQ(code, SPZ_BOUNDARY_BIT | boundary_seen++);
              break;
          }
        }
    EXPECT_EQ(cell, m.table.cell_count());
    std::uint64_t with_spectrum = 0;
    for (std::size_t n = 0; n < m.table.node_count(); ++n)
      with_spectrum += m.table.node_spectrum(n) != nullptr;
    EXPECT_EQ(h.sections[SPZ_SECTION_SPECTRA].count, with_spectrum * 81);
    std::uint64_t boundary = 0, simplices = 0;
    for (std::size_t c = 0; c < m.table.cell_count(); ++c) {
      const ExactTable::BoundaryCell* data = nullptr;
      if (m.table.cell(c, &data) == ExactTable::CellKind::boundary) {
        ++boundary;
        simplices += data->simplices.size();
      }
    }
    EXPECT_GT(boundary, 0u);
    EXPECT_EQ(h.sections[SPZ_SECTION_BOUNDARY_CELLS].count, 2 * boundary);
    EXPECT_EQ(h.sections[SPZ_SECTION_SIMPLICES].count, 4 * simplices);
    const std::uint64_t vertices = h.sections[SPZ_SECTION_BOUNDARY_PICKS].count;
    EXPECT_GT(vertices, 0u);
    EXPECT_EQ(h.sections[SPZ_SECTION_BOUNDARY_POSITIONS].count, 3 * vertices);
    EXPECT_EQ(h.sections[SPZ_SECTION_BOUNDARY_MASKS].count, 3 * vertices);
    EXPECT_EQ(h.sections[SPZ_SECTION_BOUNDARY_VALUES].count, 2 * vertices);
    EXPECT_EQ(h.sections[SPZ_SECTION_LOCUS_PLANES].count, 4 * m.sp.locus().facets());
    EXPECT_EQ(h.sections[SPZ_SECTION_SOLID_PLANES].count, refl ? 4 * m.sp.gamut().facets() : 0);
    // The node spectra are the table's, in node order, bit for bit, named by their offsets.
    const std::uint32_t* slots = o.section<std::uint32_t>(SPZ_SECTION_NODE_SLOTS);
    const float* spectra = o.section<float>(SPZ_SECTION_SPECTRA);
    std::uint32_t next = 0;
    for (std::size_t n = 0; n < m.table.node_count(); ++n) {
      const float* p = m.table.node_spectrum(n);
      if (!p) {
        ASSERT_EQ(slots[n], SPZ_OUTSIDE) << n;
        continue;
      }
      ASSERT_EQ(slots[n], 81 * next++) << n;  // the offset of its spectrum
      ASSERT_EQ(std::memcmp(spectra + slots[n], p, 81 * sizeof(float)), 0) << n;
    }
  }
}

TEST(TableFile, FetchedSpectraReproduceTheirColourWithinTheBounds) {
  // Through the reader: random Linear Rec.709 colours in [0, 1] (all in the sRGB gamut of
  // lights, nearly all in the D50 solid) are exact; the XYZ of the spectrum by the test's
  // integration is the colour's target (emission: the XYZ itself; reflectance: white balanced
  // per channel, spectralizer_checks.h) to 1e-5 (docs/DESIGN.md §3's float budget), and a
  // reflectance is within [0, 1].
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Made& m = made(mode);
    const Opened o(m.bytes);
    const test::Reference ref = test::reference_of(m.sp);
    std::mt19937 rng(mode == Mode::reflectance ? 5 : 6);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> v(81);
    int exact = 0;
    double worst = 0;
    for (int k = 0; k < 1500; ++k) {
      const float rgb[3] = {u(rng), u(rng), u(rng)};
      spz::Spectrum spec;
      if (o.view.fetch(rgb, spec) != SPZ_EXACT) continue;
      ++exact;
      spz::samples(spec, v.data());
      for (float x : v) {
        ASSERT_GE(x, 0.0f);
        if (mode == Mode::reflectance) {
          ASSERT_LE(x, 1.0f);
        }
      }
      const Xyz want =
          test::expected_target(m.sp, ref, test::rgb(test::kRec709ToXyz, rgb[0], rgb[1], rgb[2]));
      const Xyz got = test::integrate(m.sp, ref, std::vector<double>(v.begin(), v.end()));
      worst = std::max(worst, test::rel_err(got, want));
    }
    std::printf("  %s: %d exact, worst relative XYZ %.2g\n", std::string(to_string(mode)).c_str(),
                exact, worst);
    EXPECT_GT(exact, 1400);
    EXPECT_LE(worst, 1e-5);
  }
}

TEST(TableFile, BoundaryVerticesAreStoredOnceAndTheirSpectraAreTheirColours) {
  // A point where clipped cells meet is stored once, every stored one is used by a simplex,
  // and its closed-form spectrum (1 on its mask, a and b at samples i and j, else 0) has the
  // colour of its position: reflectance, the target of the RGB position (1e-5); within [0, 1].
  const Made& m = made(Mode::reflectance);
  const Opened o(m.bytes);
  const spz_file_header& h = o.h;
  const std::uint64_t count = h.sections[SPZ_SECTION_BOUNDARY_PICKS].count;
  const double* pos = o.section<double>(SPZ_SECTION_BOUNDARY_POSITIONS);
  std::set<std::tuple<double, double, double>> distinct;
  for (std::uint64_t k = 0; k < count; ++k)
    distinct.insert({pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]});
  EXPECT_EQ(distinct.size(), count);
  std::vector<bool> used(count, false);
  const std::uint32_t* sx = o.section<std::uint32_t>(SPZ_SECTION_SIMPLICES);
  for (std::uint64_t k = 0; k < h.sections[SPZ_SECTION_SIMPLICES].count; ++k)
    if (sx[k] & SPZ_BOUNDARY_BIT) {
      const std::uint32_t id = sx[k] & ~SPZ_BOUNDARY_BIT;
      ASSERT_LT(id, count);
      used[id] = true;
    }
  EXPECT_EQ(std::count(used.begin(), used.end(), true), static_cast<long>(count));
  const std::uint32_t* masks = o.section<std::uint32_t>(SPZ_SECTION_BOUNDARY_MASKS);
  const std::uint32_t* picks = o.section<std::uint32_t>(SPZ_SECTION_BOUNDARY_PICKS);
  const float* values = o.section<float>(SPZ_SECTION_BOUNDARY_VALUES);
  const test::Reference ref = test::reference_of(m.sp);
  double worst = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    std::vector<double> rho(81);
    const std::uint32_t i = picks[k] & 0xFFFF, j = picks[k] >> 16;
    for (std::uint32_t s = 0; s < 81; ++s)
      rho[s] = s == i   ? values[2 * k]
               : s == j ? values[2 * k + 1]
                        : (masks[3 * k + s / 32] >> (s % 32)) & 1u;
    for (double x : rho) {
      ASSERT_GE(x, 0.0);
      ASSERT_LE(x, 1.0);
    }
    const Xyz want = test::expected_target(
        m.sp, ref, test::rgb(test::kRec709ToXyz, pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]));
    worst = std::max(worst, test::rel_err(test::integrate(m.sp, ref, rho), want));
  }
  EXPECT_LE(worst, 1e-5);
}

// What a reader checks the table's meaning with (format version 3): each band's weights are the
// colour of a unit sample by the test's own integration of the CIE tables; sample_bound is the
// largest stored sample; max_cell_simplices the most simplices of a boundary cell.
TEST(TableFile, BandWeightsAndBoundsAreWhatTheTableHolds) {
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Made& m = made(mode);
    const Opened o(m.bytes);
    const spz_file_header& h = o.h;
    ASSERT_EQ(h.sections[SPZ_SECTION_BAND_WEIGHTS].count, 3u * 81);
    const double* w = o.section<double>(SPZ_SECTION_BAND_WEIGHTS);
    const test::Reference ref = test::reference_of(m.sp);
    for (std::size_t k = 0; k < 81; ++k) {
      std::vector<double> unit(81, 0.0);
      unit[k] = 1;
      const Xyz want = test::integrate(m.sp, ref, unit);
      const double scale = std::max({std::abs(want.X), std::abs(want.Y), std::abs(want.Z)});
      EXPECT_NEAR(w[3 * k], want.X, 1e-9 * scale + 1e-15) << k;
      EXPECT_NEAR(w[3 * k + 1], want.Y, 1e-9 * scale + 1e-15) << k;
      EXPECT_NEAR(w[3 * k + 2], want.Z, 1e-9 * scale + 1e-15) << k;
    }
    double largest = 0;
    const float* spectra = o.section<float>(SPZ_SECTION_SPECTRA);
    for (std::uint64_t k = 0; k < h.sections[SPZ_SECTION_SPECTRA].count; ++k)
      largest = std::max(largest, static_cast<double>(spectra[k]));
    const float* values = o.section<float>(SPZ_SECTION_BOUNDARY_VALUES);
    for (std::uint64_t k = 0; k < h.sections[SPZ_SECTION_BOUNDARY_VALUES].count; ++k)
      largest = std::max(largest, static_cast<double>(values[k]));
    const std::uint32_t* masks = o.section<std::uint32_t>(SPZ_SECTION_BOUNDARY_MASKS);
    for (std::uint64_t k = 0; k < h.sections[SPZ_SECTION_BOUNDARY_MASKS].count; ++k)
      if (masks[k]) largest = std::max(largest, 1.0);
    EXPECT_EQ(h.sample_bound, largest);
    if (mode == Mode::reflectance) {
      EXPECT_LE(h.sample_bound, 1.0);
    }
    std::size_t most = 0;
    for (std::size_t c = 0; c < m.table.cell_count(); ++c) {
      const ExactTable::BoundaryCell* data = nullptr;
      if (m.table.cell(c, &data) == ExactTable::CellKind::boundary)
        most = std::max(most, data->simplices.size());
    }
    EXPECT_EQ(h.max_cell_simplices, most);
    EXPECT_GT(most, 0u);
  }
}

TEST(TableFile, NamesTooLongForTheHeaderAreRefusedNamingThem) {
  const Made& m = made(Mode::emission);
  const std::string longest(103, 'c');  // 104 bytes with its NUL: the field's size
  const std::string bytes = encode_table_file(m.table, m.sp, {longest, std::string(31, 'i')});
  const Opened o(bytes);
  EXPECT_EQ(field(o.h.colorspace, sizeof o.h.colorspace), longest);
  EXPECT_EQ(field(o.h.interop_id, sizeof o.h.interop_id), std::string(31, 'i'));
  auto long_name = [&] { (void)encode_table_file(m.table, m.sp, {longest + "c", ""}); };
  test::expect_error_mentioning(long_name, {"colour space", longest.substr(0, 40), "103 bytes"},
                                "104-byte colour space");
  auto long_id = [&] { (void)encode_table_file(m.table, m.sp, {"sRGB", std::string(32, 'i')}); };
  test::expect_error_mentioning(long_id, {"interop ID", std::string(20, 'i'), "31 bytes"},
                                "32-byte interop ID");
}

}  // namespace
}  // namespace spectralize
