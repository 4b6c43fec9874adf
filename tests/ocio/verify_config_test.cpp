// verify_config.cpp -- self-contained check of ocio_configs/spectralize.ocio.
//
// Build & run (Debian 12, OpenColorIO 2.1):
//   g++ -std=c++17 -O2 -Wall -Wextra verify_config.cpp -o verify_config -lOpenColorIO
//   ./verify_config [path/to/spectralize.ocio]
//
// Config path: argv[1], else the SPECTRALIZE_OCIO_CONFIG environment variable,
// else the compile-time SPECTRALIZE_OCIO_CONFIG_PATH macro, else
// "ocio_configs/spectralize.ocio" / "spectralize.ocio" relative to the cwd.
//
// Prints every check; returns 0 if all pass, 1 if any fail, 2 if the config
// cannot be loaded.

#include <OpenColorIO/OpenColorIO.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace {

int g_failures = 0;
int g_checks = 0;

void check(bool ok, const std::string& what) {
  ++g_checks;
  if (!ok) ++g_failures;
  std::printf("[%s] %s\n", ok ? " OK " : "FAIL", what.c_str());
}

std::string fmt3(const double v[3]) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.10f, %.10f, %.10f)", v[0], v[1], v[2]);
  return buf;
}

// --------------------------------------------------------------------------
// Independent double-precision NPM derivation (same maths as make_matrices.py)

using Mat3 = std::array<std::array<double, 3>, 3>;
struct XY {
  double x, y;
};

const XY kD65{0.3127, 0.3290};

std::array<double, 3> xyToXYZ(XY p) {
  return {p.x / p.y, 1.0, (1.0 - p.x - p.y) / p.y};
}

double det3(const Mat3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Mat3 npm(XY r, XY g, XY b, XY w) {
  const std::array<double, 3> cols[3] = {xyToXYZ(r), xyToXYZ(g), xyToXYZ(b)};
  Mat3 P{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P[i][j] = cols[j][i];
  const auto W = xyToXYZ(w);
  const double d = det3(P);
  double S[3];
  for (int c = 0; c < 3; ++c) {  // Cramer's rule: P . S = W
    Mat3 Pc = P;
    for (int i = 0; i < 3; ++i) Pc[i][c] = W[i];
    S[c] = det3(Pc) / d;
  }
  Mat3 M{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M[i][j] = P[i][j] * S[j];
  return M;
}

// --------------------------------------------------------------------------

// The CPU processor spectralize uses: lossless optimisation only (OCIO 2.2+ otherwise takes
// approximate pow/log paths, ~5e-6 off; docs/DESIGN.md §3).
OCIO::ConstCPUProcessorRcPtr exactCpu(const OCIO::ConstProcessorRcPtr& p) {
  return p->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                     OCIO::OPTIMIZATION_LOSSLESS);
}

void applyF32(const OCIO::ConstConfigRcPtr& cfg, const char* src, const char* dst,
              const double in[3], double out[3]) {
  auto cpu = exactCpu(cfg->getProcessor(src, dst));
  float px[3] = {float(in[0]), float(in[1]), float(in[2])};
  cpu->applyRGB(px);
  for (int i = 0; i < 3; ++i) out[i] = px[i];
}

double maxAbsDiff(const double a[3], const double b[3]) {
  double m = 0.0;
  for (int i = 0; i < 3; ++i) m = std::fmax(m, std::fabs(a[i] - b[i]));
  return m;
}

// Convert src -> dst and compare against the expected value.
void checkConvert(const OCIO::ConstConfigRcPtr& cfg, const char* src, const char* dst,
                  const double in[3], const double expected[3], double tol) {
  std::string label = std::string(src) + " " + fmt3(in) + " -> " + dst;
  try {
    double out[3];
    applyF32(cfg, src, dst, in, out);
    char buf[96];
    std::snprintf(buf, sizeof buf, "  [max err %.3g, tol %.1g]", maxAbsDiff(out, expected), tol);
    check(maxAbsDiff(out, expected) <= tol,
          label + " = " + fmt3(out) + ", expected " + fmt3(expected) + buf);
  } catch (const std::exception& e) {
    check(false, label + " threw: " + e.what());
  }
}

// Double-precision white check: the optimised src -> dst processor must be a
// single MatrixTransform whose row sums (= image of RGB (1,1,1)) equal `white`.
void checkWhiteDouble(const OCIO::ConstConfigRcPtr& cfg, const char* src, const char* dst,
                      const double white[3], double tol) {
  std::string label = std::string(src) + " (1,1,1) -> " + dst + " in double";
  try {
    auto grp = cfg->getProcessor(src, dst)
                   ->getOptimizedProcessor(OCIO::OPTIMIZATION_DEFAULT)
                   ->createGroupTransform();
    auto mt = grp->getNumTransforms() == 1
                  ? std::dynamic_pointer_cast<const OCIO::MatrixTransform>(grp->getTransform(0))
                  : nullptr;
    if (!mt) {
      check(false, label + ": optimised processor is not a single matrix");
      return;
    }
    double m[16], off[4], out[3];
    mt->getMatrix(m);
    mt->getOffset(off);
    for (int i = 0; i < 3; ++i) out[i] = m[i * 4] + m[i * 4 + 1] + m[i * 4 + 2] + off[i];
    char buf[160];
    std::snprintf(buf, sizeof buf, " = (%.15f, %.15f, %.15f)  [max err %.3g, tol %.1g]", out[0],
                  out[1], out[2], maxAbsDiff(out, white), tol);
    check(maxAbsDiff(out, white) <= tol, label + buf);
  } catch (const std::exception& e) {
    check(false, label + " threw: " + e.what());
  }
}

struct SpaceSpec {
  const char* name;
  const char* encoding;
  bool isData;
  std::vector<const char*> aliases;  // must all resolve to `name`
};

const std::vector<SpaceSpec> kSpaces = {
    {"CIE-XYZ-D65", "scene-linear", false, {"cie_xyz_d65", "XYZ"}},
    {"Linear Rec.709 (sRGB)",
     "scene-linear",
     false,
     {"lin_srgb", "lin_rec709", "srgb_linear", "Utility - Linear - sRGB", "linear",
      "scene-linear Rec.709-sRGB"}},
    {"sRGB - Texture",
     "sdr-video",
     false,
     {"srgb_tx", "srgb_texture", "sRGB", "Utility - sRGB - Texture", "srgb"}},
    {"Gamma 2.2 Rec.709 - Texture", "sdr-video", false, {"g22_rec709_tx"}},
    {"Linear Rec.2020", "scene-linear", false, {"lin_rec2020", "Utility - Linear - Rec.2020"}},
    {"Linear P3-D65", "scene-linear", false, {"lin_p3d65", "Utility - Linear - P3-D65"}},
    {"Linear Adobe RGB (1998)", "scene-linear", false, {"lin_adobergb"}},
    {"Adobe RGB (1998) - Texture",
     "sdr-video",
     false,
     {"g22_adobergb_tx", "adobergb", "Adobe RGB (1998)"}},
    {"Display P3 - Texture", "sdr-video", false, {"srgb_p3d65_tx", "Display P3"}},
    {"ACEScg", "scene-linear", false, {"acescg", "ACES - ACEScg", "lin_ap1"}},
    {"ACES2065-1", "scene-linear", false, {"aces2065_1", "ACES - ACES2065-1", "lin_ap0", "aces"}},
    {"ACEScct", "log", false, {"acescct", "ACES - ACEScct", "acescct_ap1"}},
    // "data" is the data *role*; OCIO forbids an alias that equals a role name.
    {"Raw", "data", true, {"raw", "Utility - Raw", "data"}},
};

const std::vector<std::pair<const char*, const char*>> kRoles = {
    {"scene_linear", "Linear Rec.709 (sRGB)"},
    {"default", "Linear Rec.709 (sRGB)"},
    {"rendering", "Linear Rec.709 (sRGB)"},
    {"data", "Raw"},
    {"reference", "CIE-XYZ-D65"},
    {"color_timing", "ACEScct"},
    {"compositing_log", "ACEScct"},
    {"color_picking", "sRGB - Texture"},
    {"texture_paint", "sRGB - Texture"},
    {"matte_paint", "sRGB - Texture"},
    {"aces_interchange", "ACES2065-1"},
    {"cie_xyz_d65_interchange", "CIE-XYZ-D65"},
};

std::string findConfig(int argc, char** argv) {
  if (argc > 1) return argv[1];
  if (const char* env = std::getenv("SPECTRALIZE_OCIO_CONFIG")) return env;
#ifdef SPECTRALIZE_OCIO_CONFIG_PATH
  return SPECTRALIZE_OCIO_CONFIG_PATH;
#else
  for (const char* p : {"ocio_configs/spectralize.ocio", "spectralize.ocio"})
    if (std::ifstream(p).good()) return p;
  return "ocio_configs/spectralize.ocio";
#endif
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = findConfig(argc, argv);
  std::printf("OpenColorIO %s, config: %s\n", OCIO::GetVersion(), path.c_str());

  // Capture everything OCIO logs at warning level or above.
  std::string ocioLog;
  OCIO::SetLoggingLevel(OCIO::LOGGING_LEVEL_WARNING);
  OCIO::SetLoggingFunction([&ocioLog](const char* msg) { ocioLog += msg; });

  OCIO::ConstConfigRcPtr cfg;
  try {
    cfg = OCIO::Config::CreateFromFile(path.c_str());
  } catch (const std::exception& e) {
    std::printf("[FAIL] cannot load config: %s\n", e.what());
    return 2;
  }

  // ---------------------------------------------------------------- general
  try {
    cfg->validate();
    check(true, "Config::validate()");
  } catch (const std::exception& e) {
    check(false, std::string("Config::validate(): ") + e.what());
  }
  check(cfg->getMajorVersion() == 2, "profile version is 2.x (got " +
                                         std::to_string(cfg->getMajorVersion()) + "." +
                                         std::to_string(cfg->getMinorVersion()) + ")");

  // ---------------------------------------------------------------- spaces
  check(cfg->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL) ==
            int(kSpaces.size()),
        "config defines exactly " + std::to_string(kSpaces.size()) + " colour spaces");

  for (const auto& spec : kSpaces) {
    auto cs = cfg->getColorSpace(spec.name);
    if (!cs) {
      check(false, std::string("colour space '") + spec.name + "' exists");
      continue;
    }
    const bool exact = std::string(cs->getName()) == spec.name;
    check(exact && cs->getReferenceSpaceType() == OCIO::REFERENCE_SPACE_SCENE,
          std::string("colour space '") + spec.name + "' exists (scene-referred)");
    check(std::string(cs->getEncoding()) == spec.encoding && cs->isData() == spec.isData &&
              *cs->getFamily() && *cs->getDescription(),
          std::string("  '") + spec.name + "': encoding=" + cs->getEncoding() +
              ", isdata=" + (cs->isData() ? "true" : "false") + ", family=" + cs->getFamily() +
              ", has description");
    for (const char* alias : spec.aliases) {
      auto a = cfg->getColorSpace(alias);
      check(a && std::string(a->getName()) == spec.name,
            std::string("  alias '") + alias + "' -> '" + (a ? a->getName() : "<none>") + "'");
    }
    for (size_t i = 0; i < cs->getNumAliases(); ++i) {
      bool listed = false;
      for (const char* alias : spec.aliases) listed |= std::string(alias) == cs->getAlias(i);
      check(listed, std::string("  config alias '") + cs->getAlias(i) + "' is expected");
    }
  }

  // ---------------------------------------------------------------- roles
  for (const auto& role : kRoles) {
    auto cs = cfg->hasRole(role.first) ? cfg->getColorSpace(role.first) : nullptr;
    check(cs && std::string(cs->getName()) == role.second,
          std::string("role ") + role.first + " -> '" + (cs ? cs->getName() : "<none>") + "'");
  }

  // ---------------------------------------------------------------- matrices
  // The shipped MatrixTransforms must equal the NPM derived from the primaries.
  struct MatSpec {
    const char* name;
    XY r, g, b;
  };
  const MatSpec mats[] = {
      {"Linear Rec.709 (sRGB)", {0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}},
      {"Linear Rec.2020", {0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}},
      {"Linear P3-D65", {0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}},
      {"Linear Adobe RGB (1998)", {0.64, 0.33}, {0.21, 0.71}, {0.15, 0.06}},
  };
  for (const auto& m : mats) {
    auto cs = cfg->getColorSpace(m.name);
    auto tr = cs ? cs->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE) : nullptr;
    auto mt = std::dynamic_pointer_cast<const OCIO::MatrixTransform>(tr);
    if (!mt) {
      check(false, std::string(m.name) + ": to_scene_reference is a MatrixTransform");
      continue;
    }
    double m44[16], off[4];
    mt->getMatrix(m44);
    mt->getOffset(off);
    const Mat3 ref = npm(m.r, m.g, m.b, kD65);
    double err = 0.0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) err = std::fmax(err, std::fabs(m44[i * 4 + j] - ref[i][j]));
      err = std::fmax(err, std::fabs(m44[i * 4 + 3]));
      err = std::fmax(err, std::fabs(m44[12 + i]));
      err = std::fmax(err, std::fabs(off[i]));
    }
    err = std::fmax(err, std::fabs(m44[15] - 1.0));
    char buf[64];
    std::snprintf(buf, sizeof buf, " (max |diff| %.3g)", err);
    check(err <= 1e-12, std::string(m.name) + ": matrix == NPM(primaries, D65)" + buf);
  }

  // ---------------------------------------------------------------- numbers
  const double one[3] = {1.0, 1.0, 1.0};
  const double d65[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};  // 0.95045592705, 1, 1.08905775076

  // 1. Linear Rec.709 white -> D65 white.
  checkConvert(cfg, "Linear Rec.709 (sRGB)", "CIE-XYZ-D65", one, d65, 1e-6);
  checkConvert(cfg, "Linear Rec.2020", "CIE-XYZ-D65", one, d65, 1e-6);
  checkConvert(cfg, "Linear P3-D65", "CIE-XYZ-D65", one, d65, 1e-6);
  checkConvert(cfg, "Linear Adobe RGB (1998)", "CIE-XYZ-D65", one, d65, 1e-6);
  // 2. ACES whites (ACES white point, Bradford-adapted) -> D65 white.
  checkConvert(cfg, "ACEScg", "CIE-XYZ-D65", one, d65, 1e-4);
  checkConvert(cfg, "ACES2065-1", "CIE-XYZ-D65", one, d65, 1e-4);
  // Same whites with the composed matrices evaluated in double precision.
  for (const char* src : {"Linear Rec.709 (sRGB)", "Linear Rec.2020", "Linear P3-D65",
                          "Linear Adobe RGB (1998)", "ACEScg", "ACES2065-1"})
    checkWhiteDouble(cfg, src, "CIE-XYZ-D65", d65, 1e-12);

  // 3. sRGB piecewise decode: 0.5 -> ((0.5 + 0.055) / 1.055)^2.4 = 0.21404114...
  {
    const double v = std::pow((0.5 + 0.055) / 1.055, 2.4);
    const double in[3] = {0.5, 0.5, 0.5};
    const double xyz[3] = {v * d65[0], v, v * d65[2]};
    checkConvert(cfg, "sRGB - Texture", "CIE-XYZ-D65", in, xyz, 1e-6);
    const double lin[3] = {v, v, v};
    checkConvert(cfg, "sRGB - Texture", "Linear Rec.709 (sRGB)", in, lin, 1e-6);
    // Linear toe segment. ExponentWithLinearTransform derives the break
    // point and slope from (gamma, offset) so the curve is C1-continuous:
    // break (code) = offset / (gamma - 1) = 0.0392857, slope = 12.9232...,
    // i.e. NOT the rounded IEC 61966-2-1 constants 0.04045 / 12.92
    // (difference <= ~4e-7 absolute, only below the break).
    const double brk = 0.055 / (2.4 - 1.0);
    const double slope = brk / std::pow(2.4 * brk / 1.055, 2.4);
    const double toeIn[3] = {0.02, 0.02, 0.02};
    const double toe[3] = {0.02 / slope, 0.02 / slope, 0.02 / slope};
    checkConvert(cfg, "sRGB - Texture", "Linear Rec.709 (sRGB)", toeIn, toe, 1e-8);
    const double iec[3] = {0.02 / 12.92, 0.02 / 12.92, 0.02 / 12.92};
    checkConvert(cfg, "sRGB - Texture", "Linear Rec.709 (sRGB)", toeIn, iec, 5e-7);
    // encode direction: linear 0.18 -> 0.46135612950...
    const double g18[3] = {0.18, 0.18, 0.18};
    const double e = 1.055 * std::pow(0.18, 1.0 / 2.4) - 0.055;
    const double enc[3] = {e, e, e};
    checkConvert(cfg, "Linear Rec.709 (sRGB)", "sRGB - Texture", g18, enc, 1e-6);
    // pure gamma 2.2
    const double g = std::pow(0.5, 2.2);
    const double g22[3] = {g, g, g};
    checkConvert(cfg, "Gamma 2.2 Rec.709 - Texture", "Linear Rec.709 (sRGB)", in, g22, 1e-6);
    // Adobe RGB (1998): gamma 563/256 (Adobe RGB (1998) Color Image Encoding, 4.3.4.2)
    const double a = std::pow(0.5, 563.0 / 256.0);
    const double adobe[3] = {a, a, a};
    checkConvert(cfg, "Adobe RGB (1998) - Texture", "Linear Adobe RGB (1998)", in, adobe, 1e-6);
    // Display P3: the sRGB curve on P3-D65 primaries
    checkConvert(cfg, "Display P3 - Texture", "Linear P3-D65", in, lin, 1e-6);
  }

  // Cross-gamut sanity: Rec.709 -> Rec.2020 (ITU-R BT.2087 matrix, row 0/1/2 of red).
  {
    const double red[3] = {1.0, 0.0, 0.0};
    const double exp[3] = {0.6274039, 0.0690973, 0.0163914};
    checkConvert(cfg, "Linear Rec.709 (sRGB)", "Linear Rec.2020", red, exp, 1e-6);
  }

  // ACEScct: code value for 0.18 is (log2(0.18) + 9.72) / 17.52 = 0.4135884...
  {
    const double cv = (std::log2(0.18) + 9.72) / 17.52;
    const double in[3] = {cv, cv, cv};
    const double g18[3] = {0.18, 0.18, 0.18};
    checkConvert(cfg, "ACEScct", "ACEScg", in, g18, 1e-5);
    double viaCct[3], viaCg[3];
    applyF32(cfg, "ACEScct", "CIE-XYZ-D65", in, viaCct);
    applyF32(cfg, "ACEScg", "CIE-XYZ-D65", g18, viaCg);
    checkConvert(cfg, "ACEScct", "CIE-XYZ-D65", in, viaCg, 1e-5);
    check(maxAbsDiff(viaCct, viaCg) <= 1e-5, "ACEScct and ACEScg agree in XYZ for mid-grey");
    // below the ACEScct toe break (linear segment) round-trips too
    const double low[3] = {0.001, 0.002, 0.004};
    double cct[3], back[3];
    applyF32(cfg, "ACEScg", "ACEScct", low, cct);
    applyF32(cfg, "ACEScct", "ACEScg", cct, back);
    check(maxAbsDiff(back, low) <= 1e-6, "ACEScg -> ACEScct -> ACEScg round trip " + fmt3(low));
  }

  // Raw is data: conversions are a no-op.
  {
    const double v[3] = {0.25, 0.5, 2.0};
    checkConvert(cfg, "Raw", "CIE-XYZ-D65", v, v, 0.0);
    checkConvert(cfg, "Linear Rec.2020", "Raw", v, v, 0.0);
  }

  // ---------------------------------------------------------------- display
  {
    check(std::string(cfg->getDefaultDisplay()) == "sRGB",
          std::string("default display is 'sRGB' (got '") + cfg->getDefaultDisplay() + "')");
    bool hasStd = false, hasRaw = false;
    for (int i = 0; i < cfg->getNumViews("sRGB"); ++i) {
      hasStd |= std::string(cfg->getView("sRGB", i)) == "Standard";
      hasRaw |= std::string(cfg->getView("sRGB", i)) == "Raw";
    }
    check(hasStd && hasRaw, "display 'sRGB' has views 'Standard' and 'Raw'");
    try {
      auto dvt = OCIO::DisplayViewTransform::Create();
      dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
      dvt->setDisplay("sRGB");
      dvt->setView("Standard");
      auto cpu = exactCpu(cfg->getProcessor(dvt));
      float px[3] = {0.18f, 0.18f, 0.18f};
      cpu->applyRGB(px);
      const double e = 1.055 * std::pow(0.18, 1.0 / 2.4) - 0.055;
      const double out[3] = {px[0], px[1], px[2]}, exp[3] = {e, e, e};
      check(maxAbsDiff(out, exp) <= 1e-6, "scene_linear 0.18 -> (sRGB, Standard) = " + fmt3(out));
    } catch (const std::exception& e) {
      check(false, std::string("(sRGB, Standard) processor threw: ") + e.what());
    }
  }

  // ---------------------------------------------------------------- log
  check(ocioLog.empty(), ocioLog.empty() ? std::string("OCIO logged no warnings/errors")
                                         : "OCIO logged: " + ocioLog);

  std::printf("\n%d checks, %d failed\n", g_checks, g_failures);
  return g_failures == 0 ? 0 : 1;
}
