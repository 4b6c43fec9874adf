// The render-time evaluator (include/spectralize/rt.hpp) under hostile input: tables it did
// not make (crafted from genuine ones, their checksums made valid again, as anyone can), the
// C++ Table's lifetime (failed reloads, moves, empty tables), and colours a shading network can
// compute (huge, tiny, NaN, every 8-bit colour). Truths: loading costs O(size) and refuses a
// table whose bytes say something other than a table (naming the field); every fetch that
// succeeds gives a finite spectrum >= 0 (<= 1 for reflectances, bit for bit), SPZ_EXACT only
// when it reproduces the colour (the test's own matrix and the table's band weights, relative
// 1e-5) at any magnitude; no input is undefined behaviour (the sanitized build aborts on any).

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <spectralize/rt.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_reproduction.h"
#include "test_support.h"

namespace spectralize {
namespace {

namespace fs = std::filesystem;

std::string table_path(const std::string& name) {
  return std::string(SPECTRALIZE_RT_TABLES) + "/" + name + ".spztab";
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A scratch folder, removed afterwards.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() /
          ("spz-hostile-" + std::to_string(::getpid()) + "-" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string p = (dir / name).string();
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return p;
  }
};

// A genuine table's bytes, to be edited: the header as a struct, values at sections, and the
// checksum made valid again (what anyone crafting a table does).
struct Crafted {
  std::string bytes;
  explicit Crafted(const std::string& name) : bytes(read_bytes(table_path(name))) {
    EXPECT_GT(bytes.size(), 4096u) << name;
  }
  spz_file_header& header() { return *reinterpret_cast<spz_file_header*>(bytes.data()); }
  template <typename T>
  T* section(int s) {
    return reinterpret_cast<T*>(bytes.data() + header().sections[s].offset);
  }
  std::uint64_t count(int s) { return header().sections[s].count; }
  std::string sealed() {
    std::string b = bytes;
    std::memset(b.data() + 24, 0, 8);
    const std::uint64_t sum =
        spz::detail::table_checksum(reinterpret_cast<const unsigned char*>(b.data()), b.size());
    std::memcpy(b.data() + 24, &sum, 8);
    return b;
  }
};

// Loads `path` with the C++ API: the error message ("" when it loads).
std::string load_error(const std::string& path) {
  spz::Table t;
  std::string error;
  return t.load(path.c_str(), &error) ? std::string() : error;
}

void expect_refused(const std::string& path, const std::string& word) {
  const std::string error = load_error(path);
  EXPECT_FALSE(error.empty()) << path << " loads";
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find(word), std::string::npos) << error;
}

// The bytes this process has read with read(2) and friends so far (the kernel's rchar, in
// /proc/self/io): a count no load changes. Cost: one small file read (its own bytes included,
// the same each time).
std::uint64_t bytes_read_so_far() {
  std::ifstream io("/proc/self/io");
  std::string key;
  std::uint64_t value = 0;
  while (io >> key >> value)
    if (key == "rchar:") return value;
  return 0;
}

// The spectrum's samples (the C++ API); their colour: spz_test::relative_error.
std::vector<float> samples_of(const spz::Spectrum& s) {
  std::vector<float> out(spz::bands(s));
  spz::samples(s, out.data());
  return out;
}

// --- Load cost and meaning ---

// The loader's tolerance serves fetch's promise: node spectra 1.1e-5 off their colours (the
// fuzzer's table, which loaded and then called a blend of such nodes exact at 1.04e-5) are
// refused, as is a node 3e-6 off; spectra within 1e-6 load and every exact fetch of 20,000
// random colours then reproduces its colour to 1e-5. Negative band weights (no observer or
// illuminant has them) are refused.
TEST(RtHostile, NodesLoadOnlyWhenTheirBlendsKeepTheExactPromise) {
  Scratch s;
  for (const char* name : {"srgb_reflectance", "srgb_emission"}) {
    SCOPED_TRACE(name);
    for (const float off : {1.1e-5f, 3e-6f}) {
      Crafted c(name);
      float* spectra = c.section<float>(SPZ_SECTION_SPECTRA);
      const std::uint32_t bands = c.header().bands;
      // The second spectrum (a node's: the first may be black's zero), every sample.
      for (std::uint32_t k = 0; k < bands; ++k) spectra[bands + k] *= 1 + off;
      expect_refused(s.write("off.spztab", c.sealed()), "does not reproduce");
    }
    Crafted c(name);
    float* spectra = c.section<float>(SPZ_SECTION_SPECTRA);
    const std::uint64_t n = c.count(SPZ_SECTION_SPECTRA);
    // Every spectrum 1e-6 brighter (within the loader's 2e-6; reflectances kept <= 1).
    for (std::uint64_t k = 0; k < n; ++k)
      spectra[k] = std::min(spectra[k] * (1 + 1e-6f),
                            c.header().sample_bound > 1 ? std::numeric_limits<float>::max() : 1.0f);
    const std::string path = s.write("within.spztab", c.sealed());
    ASSERT_EQ(load_error(path), "");
    spz::Table t;
    ASSERT_TRUE(t.load(path.c_str()));
    const spz::TableView& v = t.view();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int exact = 0, off = 0;
    for (int i = 0; i < 20000; ++i) {
      const float col[3] = {u(rng), u(rng), u(rng)};
      spz::Spectrum sp{};
      if (v.fetch(col, sp) != SPZ_EXACT) continue;
      ++exact;
      off += spz_test::relative_error(v, samples_of(sp), col) > 1e-5;
    }
    EXPECT_GT(exact, 10000);
    EXPECT_EQ(off, 0) << "of " << exact;
  }
  Crafted c("srgb_reflectance");
  c.section<double>(SPZ_SECTION_BAND_WEIGHTS)[3 * 40 + 2] = -1e-9;
  expect_refused(s.write("negative_weight.spztab", c.sealed()), "band weight 122 is negative");
}

// Boundary cells shared by many cells (the writer never makes them) made validation cost
// cells x simplices (32 s for 8.3 MB); now each is named once, in order, or the table is
// refused, so a refusal or a load costs time proportional to the file: the crafted table is
// refused at the second cell naming the shared boundary cell, having checked one cell's
// simplices (the cell named in the message, not the last one).
TEST(RtHostile, CraftedTablesAreRefusedInTimeProportionalToTheirSize) {
  Scratch s;
  Crafted shared("srgb_reflectance");
  std::uint32_t* cells = shared.section<std::uint32_t>(SPZ_SECTION_CELLS);
  const std::uint32_t first_boundary = [&] {
    for (std::uint64_t c = 0; c < shared.count(SPZ_SECTION_CELLS); ++c)
      if (cells[c] != SPZ_OUTSIDE && (cells[c] & SPZ_BOUNDARY_BIT)) return cells[c];
    return 0u;
  }();
  ASSERT_NE(first_boundary, 0u);
  std::vector<std::uint64_t> named;  // the cells naming it, in order
  for (std::uint64_t c = 0; c < shared.count(SPZ_SECTION_CELLS); ++c)
    if (cells[c] != SPZ_OUTSIDE) {
      cells[c] = first_boundary;  // every cell: one boundary cell
      named.push_back(c);
    }
  ASSERT_GT(named.size(), 1000u);
  const std::string p = s.write("shared.spztab", shared.sealed());
  expect_refused(p, "numbered in cell order");
  expect_refused(p, "cell " + std::to_string(named[1]) + " has code");
  // A boundary cell claiming every simplex: beyond max_cell_simplices (a fetch's bound).
  Crafted long_run("srgb_reflectance");
  std::uint32_t* bcells = long_run.section<std::uint32_t>(SPZ_SECTION_BOUNDARY_CELLS);
  bcells[1] = static_cast<std::uint32_t>(long_run.count(SPZ_SECTION_SIMPLICES) / 4);
  expect_refused(s.write("long.spztab", long_run.sealed()), "max_cell_simplices");
  // The header's bound itself is at most the format's.
  Crafted bound("srgb_reflectance");
  bound.header().max_cell_simplices = SPZ_MAX_CELL_SIMPLICES + 1;
  expect_refused(s.write("bound.spztab", bound.sealed()), "max_cell_simplices");
  EXPECT_LE(Crafted("srgb_reflectance").header().max_cell_simplices, SPZ_MAX_CELL_SIMPLICES);
}

// In-bounds tables that say something else load no more: the field is named.
TEST(RtHostile, TablesWhoseMeaningIsWrongAreRefusedNamingTheField) {
  Scratch s;
  {
    Crafted c("srgb_reflectance");
    std::memset(c.header().rgb_to_target, 0, sizeof c.header().rgb_to_target);
    expect_refused(s.write("zero_matrix.spztab", c.sealed()), "rgb_to_target");
  }
  {
    Crafted c("srgb_reflectance");
    for (double& v : c.header().target_to_rgb) v *= 1.01;
    expect_refused(s.write("inverse.spztab", c.sealed()), "target_to_rgb");
  }
  {
    Crafted c("srgb_reflectance");
    for (double& v : c.header().rgb_to_xyz) v *= 1e300;
    expect_refused(s.write("huge_matrix.spztab", c.sealed()), "rgb_to_xyz");
  }
  {
    Crafted c("srgb_reflectance");
    c.section<float>(SPZ_SECTION_AXIS_INVERSE)[3] *= 2;
    expect_refused(s.write("inverse_interval.spztab", c.sealed()), "axis inverse");
  }
  {  // A lookup bin naming the wrong interval, one without its node, one with a node not in it:
     // a lookup would find cells the colour is not in.
    for (int edit = 0; edit < 3; ++edit) {
      Crafted c("srgb_reflectance");
      spz_axis_bin* bins = c.section<spz_axis_bin>(SPZ_SECTION_AXIS_LUT);
      std::uint64_t with_node = 0;
      while (bins[with_node].split == INFINITY) ++with_node;
      if (edit == 0) bins[with_node + 1].node += 1;
      if (edit == 1) bins[with_node].split = INFINITY;
      if (edit == 2) bins[with_node + 1].split = bins[with_node].split;
      expect_refused(s.write("lookup.spztab", c.sealed()), "axis lookup entry");
    }
  }
  for (const char* name : {"srgb_reflectance", "srgb_emission"}) {
    SCOPED_TRACE(name);
    Crafted c(name);
    float* spectra = c.section<float>(SPZ_SECTION_SPECTRA);
    std::fill(spectra, spectra + c.count(SPZ_SECTION_SPECTRA), 0.0f);
    expect_refused(s.write("zero_spectra.spztab", c.sealed()), "does not reproduce");
  }
  {  // Planes that reject every colour (offsets far below any).
    Crafted c("srgb_reflectance");
    double* planes = c.section<double>(SPZ_SECTION_SOLID_PLANES);
    for (std::uint64_t f = 0; f < c.count(SPZ_SECTION_SOLID_PLANES) / 4; ++f)
      planes[4 * f + 3] = -1;
    expect_refused(s.write("reject.spztab", c.sealed()), "rejects node");
  }
  {  // Every node naming one spectrum: the nodes' colours are not its colour.
    Crafted c("srgb_reflectance");
    std::uint32_t* slots = c.section<std::uint32_t>(SPZ_SECTION_NODE_SLOTS);
    for (std::uint64_t n = 0; n < c.count(SPZ_SECTION_NODE_SLOTS); ++n)
      if (slots[n] != SPZ_OUTSIDE) slots[n] = 0;
    expect_refused(s.write("one_slot.spztab", c.sealed()), "does not reproduce");
  }
  {  // Band weights of another table (its spectra no longer reproduce their positions).
    Crafted c("srgb_reflectance");
    double* w = c.section<double>(SPZ_SECTION_BAND_WEIGHTS);
    for (std::uint64_t k = 0; k < c.count(SPZ_SECTION_BAND_WEIGHTS); ++k) w[k] *= 1.1;
    expect_refused(s.write("weights.spztab", c.sealed()), "does not reproduce");
  }
  {  // Light that no spectrum of X+Y+Z = 1 holds: a sample of 3e38.
    Crafted c("srgb_emission");
    c.section<float>(SPZ_SECTION_SPECTRA)[40] = 3e38f;
    c.header().sample_bound = 3e38;
    expect_refused(s.write("bright.spztab", c.sealed()), "sample_bound");
  }
  {  // A sample beyond the stated bound.
    Crafted c("srgb_emission");
    c.section<float>(SPZ_SECTION_SPECTRA)[40] = static_cast<float>(c.header().sample_bound * 2);
    expect_refused(s.write("beyond.spztab", c.sealed()), "sample_bound");
  }
  {  // A wavelength step a float cannot invert (eval's cast), and one of a tenth of a nanometre
     // too many steps long.
    Crafted c("srgb_emission");
    c.header().lambda_step = 1e-300;
    expect_refused(s.write("step.spztab", c.sealed()), "lambda_step");
  }
  {  // A snap tolerance that would call any colour exact.
    Crafted c("srgb_reflectance");
    c.header().snap_tolerance = 0.5;
    expect_refused(s.write("snap.spztab", c.sealed()), "snap_tolerance");
  }
  {  // Counts that disagree name the section.
    Crafted c("srgb_emission");
    c.header().nodes[0] += 1;
    expect_refused(s.write("nodes.spztab", c.sealed()), "section 'axis x'");
  }
}

// The header is read and checked before the rest: a 1 GiB file that is no table costs one read
// of 1024 bytes, not 1 GB of memory and a second of reading (counted by the kernel: the
// bytes the process read while loading it).
TEST(RtHostile, TheHeaderIsCheckedBeforeTheRestIsRead) {
  Scratch s;
  const std::string p = (s.dir / "big.bin").string();
  {
    std::ofstream f(p, std::ios::binary);
    f << "NOTATABLE";
  }
  ASSERT_EQ(::truncate(p.c_str(), 1l << 30), 0);  // sparse: no disk used
  const std::uint64_t before = bytes_read_so_far();
  (void)load_error(p);
  const std::uint64_t read = bytes_read_so_far() - before;
  EXPECT_LT(read, 64u << 10) << "bytes read to refuse a 1 GiB file";
  expect_refused(p, "no SPZTABLE signature");
  // A genuine header claiming another size: refused by the header alone.
  Crafted c("srgb_emission");
  std::string cut = c.bytes.substr(0, c.bytes.size() / 2);
  expect_refused(s.write("cut.spztab", cut), "truncated: file_size says");
  // An older version: made again, says the message.
  Crafted old("srgb_emission");
  old.header().version = 2;
  expect_refused(s.write("v2.spztab", old.sealed()),
                 "make the table again with `spectralize table`");
}

// --- The C++ Table's lifetime ---

TEST(RtHostile, ATableThatFailsToReloadIsEmptyNotDangling) {
  spz::Table t;
  ASSERT_TRUE(t.load(table_path("srgb_reflectance").c_str()));
  spz::Spectrum s{};
  const float rgb[3] = {0.2f, 0.5f, 0.3f};
  ASSERT_EQ(t.view().fetch(rgb, s), SPZ_EXACT);
  // The file is briefly missing while a renderer watches it: the load fails, the data go, and
  // the view with them (a fetch from the old view would read freed memory under ASan).
  EXPECT_FALSE(t.load("/nonexistent/srgb.spztab"));
  EXPECT_FALSE(t.view().loaded());
  spz::Spectrum z{};
  EXPECT_EQ(t.view().fetch(rgb, z), SPZ_INVALID);
  EXPECT_EQ(spz::eval(z, 550.0f), 0.0f);
  EXPECT_EQ(spz::bands(z), 0u);
}

TEST(RtHostile, MovedFromAndEmptyTablesFetchTheZeroSpectrum) {
  spz::Table empty;
  spz::Spectrum s{};
  const float rgb[3] = {0.2f, 0.5f, 0.3f};
  EXPECT_EQ(empty.view().fetch(rgb, s), SPZ_INVALID);
  float four[4] = {1, 1, 1, 1};
  const float lambdas[4] = {400, 500, 600, 700};
  spz::eval4(s, lambdas, four);
  for (float v : four) EXPECT_EQ(v, 0.0f);
  // A spectrum fetched before a move stays valid: the view lives with the bytes, not in the
  // Table object.
  spz::Table a;
  ASSERT_TRUE(a.load(table_path("srgb_reflectance").c_str()));
  ASSERT_EQ(a.view().fetch(rgb, s), SPZ_EXACT);
  const float before = spz::eval(s, 550.0f);
  spz::Table b(std::move(a));
  EXPECT_EQ(spz::eval(s, 550.0f), before);
  spz::Spectrum moved{};
  EXPECT_EQ(a.view().fetch(rgb, moved), SPZ_INVALID);  // NOLINT: a moved-from table, on purpose
  EXPECT_EQ(spz::eval(moved, 550.0f), 0.0f);
  spz::Table c;
  c = std::move(b);
  EXPECT_EQ(spz::eval(s, 550.0f), before);
  // A zero-initialised spectrum is the zero spectrum, through the C API too.
  const spz_spectrum zero{};
  EXPECT_EQ(spz_eval(&zero, 550.0f), 0.0f);
  float out[8];
  std::fill(out, out + 8, 7.0f);
  EXPECT_EQ(spz_samples_n(&zero, out, 8), 0u);
  for (float v : out) EXPECT_EQ(v, 0.0f);
  spz_spectrum from_null{};
  EXPECT_EQ(spz_fetch(nullptr, rgb, &from_null), SPZ_INVALID);
  EXPECT_EQ(spz_eval(&from_null, 500.0f), 0.0f);
}

// spz_samples_n never writes beyond the capacity given: a consumer sized for fewer bands learns
// the count and gets nothing written.
TEST(RtHostile, SamplesWithACapacityNeverOverrun) {
  spz::Table t;
  ASSERT_TRUE(t.load(table_path("srgb_emission").c_str()));
  spz::Spectrum s{};
  const float rgb[3] = {0.2f, 0.5f, 0.3f};
  ASSERT_EQ(t.view().fetch(rgb, s), SPZ_EXACT);
  std::vector<float> small(10, -1.0f);
  EXPECT_EQ(spz_samples_n(&s, small.data(), small.size()), 81u);
  for (float v : small) EXPECT_EQ(v, -1.0f);
  std::vector<float> room(100, -1.0f);
  EXPECT_EQ(spz_samples_n(&s, room.data(), room.size()), 81u);
  EXPECT_EQ(room[81], -1.0f);
  EXPECT_EQ(spz_spectrum_bands(&s), 81u);
  for (std::size_t k = 0; k < 81; ++k) EXPECT_GE(room[k], 0.0f);
}

// --- Colours ---

// Every status that says a spectrum was made gives a finite one: lights too bright for float
// are SPZ_INVALID (their samples would be inf or NaN), whatever the channels.
TEST(RtHostile, LightsTooBrightForFloatAreInvalidNeverNanCalledExact) {
  for (const char* name : {"srgb_emission", "acescg_emission"}) {
    SCOPED_TRACE(name);
    spz::Table t;
    ASSERT_TRUE(t.load(table_path(name).c_str()));
    const float big = 3e38f, max = std::numeric_limits<float>::max();
    const float colours[][3] = {{big, big, big}, {0, 0, big},      {big, 0.5f, 0.5f},
                                {max, max, max}, {1e30f, 1, 1},    {1e37f, 1e37f, 1e37f},
                                {0.5f, max, 0},  {2e38f, 0, 2e38f}};
    for (const auto& c : colours) {
      spz::Spectrum s{};
      const int status = t.view().fetch(c, s);
      if (status < 0) {
        for (float v : samples_of(s)) EXPECT_EQ(v, 0.0f);
        continue;
      }
      for (float v : samples_of(s)) {
        ASSERT_TRUE(std::isfinite(v)) << c[0] << "," << c[1] << "," << c[2] << " status " << status;
        ASSERT_GE(v, 0.0f);
      }
    }
  }
}

// NaN, infinities and the extremes of float: statuses, never undefined behaviour (this suite
// runs in the sanitized build with -fno-sanitize-recover: a float-to-integer cast of a NaN
// aborts it).
TEST(RtHostile, NanAndInfiniteColoursAreInvalidOnEveryTable) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float lowest = std::numeric_limits<float>::denorm_min();
  for (const char* name : {"srgb_reflectance", "rec2020_reflectance", "acescg_reflectance",
                           "srgb_emission", "rec2020_emission", "acescg_emission"}) {
    SCOPED_TRACE(name);
    spz::Table t;
    ASSERT_TRUE(t.load(table_path(name).c_str()));
    const float invalid[][3] = {{nan, 0.5f, 0.5f}, {0.5f, nan, 0.5f}, {0.5f, 0.5f, nan},
                                {inf, 0.5f, 0.5f}, {-inf, 0, 0},      {nan, nan, nan}};
    for (const auto& c : invalid) {
      spz::Spectrum s{};
      EXPECT_EQ(t.view().fetch(c, s), SPZ_INVALID);
      for (float v : samples_of(s)) EXPECT_EQ(v, 0.0f);
    }
    const float odd[][3] = {{lowest, 0, 0},
                            {lowest, lowest, lowest},
                            {-0.0f, -0.0f, -0.0f},
                            {1e-38f, 1e-38f, 1e-38f},
                            {1e20f, -1e20f, 1e20f}};
    for (const auto& c : odd) {
      spz::Spectrum s{};
      const int status = t.view().fetch(c, s);
      for (float v : samples_of(s)) {
        ASSERT_TRUE(std::isfinite(v)) << status;
        ASSERT_GE(v, 0.0f) << status;
      }
    }
    // eval at hostile wavelengths: 0, never a cast of NaN.
    spz::Spectrum s{};
    const float grey[3] = {0.4f, 0.4f, 0.4f};
    ASSERT_GE(t.view().fetch(grey, s), 0);
    for (float l : {nan, inf, -inf, -1.0f, 1e30f}) EXPECT_EQ(spz::eval(s, l), 0.0f);
    const float lambdas[4] = {nan, inf, -inf, 1e30f};
    float out[4];
    spz::eval4(s, lambdas, out);
    for (float v : out) EXPECT_EQ(v, 0.0f);
  }
}

// Relative at any magnitude: a colour near black is SPZ_EXACT only if its spectrum reproduces
// it to 1e-5 of itself. ACEScg's pure red is outside the reflectance solid at every scale
// (mapped), never exact by an absolute tolerance; in-gamut wide-gamut colours scaled down to
// 1e-30 reproduce themselves whenever they say so.
TEST(RtHostile, DarkColoursAreExactOnlyRelativeToThemselves) {
  for (const char* name : {"acescg_reflectance", "rec2020_reflectance"}) {
    SCOPED_TRACE(name);
    spz::Table t;
    ASSERT_TRUE(t.load(table_path(name).c_str()));
    const spz::TableView& v = t.view();
    ASSERT_GT(v.header().sections[SPZ_SECTION_BAND_WEIGHTS].count, 0u);
    if (std::string(name) == "acescg_reflectance") {
      for (double k = 1; k >= 1e-35; k /= 10) {
        const float c[3] = {static_cast<float>(k), 0, 0};
        spz::Spectrum s{};
        const int status = v.fetch(c, s);
        EXPECT_EQ(status, SPZ_MAPPED) << "red at " << k;
      }
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int exact = 0, off = 0;
    for (int i = 0; i < 2000; ++i) {
      const float base[3] = {u(rng), u(rng), u(rng)};
      for (double scale : {1e-3, 1e-8, 1e-12, 1e-15, 1e-20, 1e-30}) {
        const float c[3] = {static_cast<float>(base[0] * scale),
                            static_cast<float>(base[1] * scale),
                            static_cast<float>(base[2] * scale)};
        spz::Spectrum s{};
        if (v.fetch(c, s) != SPZ_EXACT) continue;
        ++exact;
        if (spz_test::relative_error(v, samples_of(s), c) > 1e-5) ++off;
      }
    }
    EXPECT_GT(exact, 2000);
    EXPECT_EQ(off, 0) << "of " << exact << " colours called exact";
  }
}

// Bit-exact bounds: every 8-bit sRGB colour (decoded as a renderer decodes it) on the sRGB
// reflectance table of every model gets weights >= 0 and samples in [0, 1]; so do greys next to
// black and white.
TEST(RtHostile, EveryEightBitColourHasBoundedWeightsAndSamplesOnEveryModel) {
  float decode[256];
  for (int i = 0; i < 256; ++i) {
    const double v = i / 255.0;
    decode[i] = static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
  }
  for (const char* name : {"srgb_reflectance", "srgb_reflectance_natural",
                           "srgb_reflectance_smooth", "srgb_reflectance_paper"}) {
    SCOPED_TRACE(name);
    spz::Table t;
    ASSERT_TRUE(t.load(table_path(name).c_str()));
    const spz::TableView& v = t.view();
    std::vector<float> x(v.bands());
    std::uint64_t negative_weights = 0, negative_samples = 0, above_one = 0, failed = 0;
    auto check = [&](const float c[3]) {
      spz::Spectrum s{};
      if (v.fetch(c, s) < 0) {
        ++failed;
        return;
      }
      for (float w : s.weight) negative_weights += w < 0.0f;
      spz::samples(s, x.data());
      for (float y : x) {
        negative_samples += y < 0.0f;
        above_one += y > 1.0f;
      }
    };
    for (int r = 0; r < 256; ++r)
      for (int g = 0; g < 256; ++g)
        for (int b = 0; b < 256; ++b) {
          const float c[3] = {decode[r], decode[g], decode[b]};
          check(c);
        }
    for (double e : {1e-30, 1e-20, 1e-12, 1e-9, 1e-7, 1e-5}) {
      const float dark[3] = {static_cast<float>(e), static_cast<float>(e), static_cast<float>(e)};
      const float light = static_cast<float>(1 - e);
      const float bright[3] = {light, light, light};
      check(dark);
      check(bright);
    }
    EXPECT_EQ(failed, 0u);
    EXPECT_EQ(negative_weights, 0u);
    EXPECT_EQ(negative_samples, 0u);
    EXPECT_EQ(above_one, 0u);
  }
}

// At the nodes, where rounding decides the interval: every colour whose channels are on [0, 1]
// at a node of the squared axes ((k / 24)^2, docs/DESIGN.md §14, as the test computes them) or
// within 2 floats of one, on the sRGB and ACEScg reflectance tables, gets weights >= 0 summing
// to 1 (none: black, below kDarkest) and, when it is said to be exact, reproduces itself to 1e-5
// (the test's own matrix and the table's band weights).
TEST(RtHostile, ColoursAtAndBesideEveryNodeHaveConvexWeightsAndAreExact) {
  std::vector<float> at;
  for (int k = 0; k <= 24; ++k) {
    const double x = k / 24.0;
    float p = static_cast<float>(x * x);
    for (int i = 0; i < 2; ++i) p = std::nextafter(p, -1.0f);
    for (int i = 0; i < 5; ++i, p = std::nextafter(p, 2.0f))
      if (p >= 0.0f && p <= 1.0f) at.push_back(p);
  }
  for (const char* name : {"srgb_reflectance", "acescg_reflectance"}) {
    SCOPED_TRACE(name);
    spz::Table t;
    ASSERT_TRUE(t.load(table_path(name).c_str()));
    const spz::TableView& v = t.view();
#if defined(__SSE2__)
    EXPECT_TRUE(v.direct_lookup());  // the path these colours take where SSE2 is
#endif
    std::uint64_t exact = 0, off = 0, negative = 0, unit = 0, failed = 0;
    std::vector<float> x(v.bands());
    for (float r : at)
      for (float g : at)
        for (float b : at) {
          const float c[3] = {r, g, b};
          spz::Spectrum s{};
          const int status = v.fetch(c, s);
          if (status < 0) {
            ++failed;
            continue;
          }
          double sum = 0;
          for (float wk : s.weight) negative += wk < 0.0f, sum += wk;
          // Colours darker than kDarkest are black: no weights at all.
          if (std::max({r, g, b}) >= spz::TableView::kDarkest) unit += std::abs(sum - 1) > 1e-6;
          if (status != SPZ_EXACT) continue;
          ++exact;
          spz::samples(s, x.data());
          off += spz_test::relative_error(v, x, c) > 1e-5;
        }
    std::printf("  %s: %zu^3 colours at and beside the nodes, %llu exact\n", name, at.size(),
                static_cast<unsigned long long>(exact));
    EXPECT_EQ(failed, 0u);
    EXPECT_EQ(negative, 0u);
    EXPECT_EQ(unit, 0u);
    EXPECT_GT(exact, at.size() * at.size());
    EXPECT_EQ(off, 0u) << "of " << exact << " colours called exact";
  }
}

}  // namespace
}  // namespace spectralize
