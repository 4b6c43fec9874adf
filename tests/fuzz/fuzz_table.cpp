// libFuzzer target: the .spztab loader (include/spectralize/rt_impl.hpp) on any bytes, its checksum
// made valid so that mutations reach the validation of sizes, offsets, indices, values and
// meaning; a table it accepts is then looked up on hostile colours (fixed ones, and colours made
// of the input's own bytes) and every result is checked, not only for crashes: a status >= 0
// gives weights >= 0 and finite samples >= 0 (<= 1 for reflectances); SPZ_EXACT reproduces the
// colour under the table's own band weights to 1e-5 relative, at any magnitude; eval at hostile
// wavelengths is finite. Never a read outside the bytes (AddressSanitizer), never undefined
// behaviour (UndefinedBehaviorSanitizer). Seeds: LLVMFuzzerInitialize writes small valid tables
// of both modes, every model and two wavelength steps into the first corpus folder when they
// are missing.
// The target's one unit: it compiles the loader (include/spectralize/rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "../unit/rt_reproduction.h"
#include "core/tables/exact_table.h"
#include "core/tables/spectral_table.h"
#include "core/tables/table_file.h"

using namespace spectralize;

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  for (int i = 1; i < *argc; ++i) {
    const std::string arg = (*argv)[i];
    if (arg.empty() || arg[0] == '-' || !std::filesystem::is_directory(arg)) continue;
    for (const char* model : {"exemplar", "natural", "smooth", "paper"})
      for (int step : {20, 10})
        for (int mode = 0; mode < 2; ++mode) {
          const std::filesystem::path seed =
              std::filesystem::path(arg) /
              ("seed_" + std::string(mode ? "reflectance" : "emission") + "_" + model + "_" +
               std::to_string(step) + ".spztab");
          if (std::filesystem::exists(seed)) continue;
          SpectralizerSettings s;
          s.grid = WavelengthGrid(400, 700, step);
          s.mode = mode ? Mode::reflectance : Mode::emission;
          s.model = model;
          const Spectralizer sp(s);
          ExactTable table(sp, kRec709Frame, TableResolution{2, 1, 6});
          table.build();
          const std::string bytes = encode_table_file(table, sp, {"Linear Rec.709 (sRGB)", ""});
          std::ofstream(seed, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        }
    break;
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint64_t> aligned(size / 8 + 1);
  std::memcpy(aligned.data(), data, size);
  auto* bytes = reinterpret_cast<unsigned char*>(aligned.data());
  if (size >= 32) {
    std::memset(bytes + 24, 0, 8);
    const std::uint64_t sum = spz::detail::table_checksum(bytes, size);
    std::memcpy(bytes + 24, &sum, 8);
  }
  spz::TableView view;
  char error[256];
  if (!view.open(bytes, size, error, sizeof error)) return 0;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float big = std::numeric_limits<float>::max();
  std::vector<std::array<float, 3>> colours = {
      {0.2f, 0.5f, 0.1f}, {1, 1, 1},      {0, 0, 0},          {-0.3f, 1.2f, 0.4f},
      {5, -1, 2},         {nan, 0, 0},    {1e30f, 1, 1},      {big, big, big},
      {0, 0, 3e38f},      {inf, 1, 1},    {1e-30f, 0, 0},     {1e-12f, 1e-12f, 1e-13f},
      {0.5f, 0.5f, 0.5f}, {1e-40f, 0, 0}, {0.9999999f, 1, 1}, {0.03f, 0.7f, 0.02f}};
  // Colours of the input's last bytes: whatever a shading network computes.
  if (size >= 1024 + 12) {
    std::array<float, 3> c;
    std::memcpy(c.data(), data + size - 12, 12);
    colours.push_back(c);
  }
  const float lambda[4] = {380, 455.5f, 600, 900};
  const float hostile[4] = {nan, inf, -inf, 1e30f};
  std::vector<float> out(view.bands());
  for (const auto& c : colours) {
    spz::Spectrum s;
    const int status = view.fetch(c.data(), s);
    spz::samples(s, out.data());
    float v[4];
    spz::eval4(s, lambda, v);
    for (float x : v)
      if (!std::isfinite(x)) __builtin_trap();
    spz::eval4(s, hostile, v);
    for (float x : v)
      if (x != 0.0f) __builtin_trap();
    if (status < 0) {
      for (float x : out)
        if (x != 0.0f) __builtin_trap();  // the zero spectrum
      continue;
    }
    for (float w : s.weight)
      if (!(w >= 0.0f)) __builtin_trap();
    for (float x : out)
      if (!(x >= 0) || !std::isfinite(x) || (view.reflectance() && x > 1)) __builtin_trap();
    if (status == SPZ_EXACT && spz_test::relative_error(view, out, c.data()) > 1e-5)
      __builtin_trap();
    (void)spz::eval(s, 550);
  }
  return 0;
}
