// libFuzzer target: the .spztab loader (include/spectralize/rt.hpp) on any bytes, its checksum
// made valid so that mutations reach the validation of sizes, offsets, indices and values; a
// table it accepts is then looked up and evaluated on a few colours. Never a crash, never a
// read outside the bytes (AddressSanitizer), spectra finite and within their bounds.
// Seed: LLVMFuzzerInitialize writes a small valid table (coarse grids, both modes alternate)
// into the first corpus folder when it has none.
#include <spectralize/rt.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/exact_table.h"
#include "core/spectral_table.h"
#include "core/table_file.h"

using namespace spectralize;

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  for (int i = 1; i < *argc; ++i) {
    const std::string arg = (*argv)[i];
    if (arg.empty() || arg[0] == '-' || !std::filesystem::is_directory(arg)) continue;
    for (int mode = 0; mode < 2; ++mode) {
      const std::filesystem::path seed =
          std::filesystem::path(arg) / (mode ? "seed_reflectance.spztab" : "seed_emission.spztab");
      if (std::filesystem::exists(seed)) continue;
      SpectralizerSettings s;
      s.grid = WavelengthGrid(400, 700, 20);
      s.mode = mode ? Mode::reflectance : Mode::emission;
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
  const float colours[][3] = {{0.2f, 0.5f, 0.1f}, {1, 1, 1},   {0, 0, 0},    {-0.3f, 1.2f, 0.4f},
                              {5, -1, 2},         {NAN, 0, 0}, {1e30f, 1, 1}};
  const float lambda[4] = {380, 455.5f, 600, 900};
  std::vector<float> out(view.bands());
  for (const auto& c : colours) {
    spz::Spectrum s;
    view.fetch(c, s);
    spz::samples(s, out.data());
    float v[4];
    spz::eval4(s, lambda, v);
    for (float x : out)
      if (!(x >= 0) || !std::isfinite(x) || (view.reflectance() && x > 1)) __builtin_trap();
    (void)spz::eval(s, 550);
  }
  return 0;
}
