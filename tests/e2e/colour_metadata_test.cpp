// Colour metadata through the real binary (the guide's "Files and guarantees"
// (docs/guide/files.md), Metadata tells the truth; the guide's "Honest colour tags"
// (docs/guide/pipeline.md)): written RGB carries the tags of its own colour space (the previews,
// --to-rgb's EXR chromaticities and interop IDs, the ICC profiles of TIFF, PNG and JPEG), and a
// format with no slot for the space gets a counted warning; an input's ICC profile or PNG gamma is
// honoured or named with the space assumed; channel sets that are not colour and spectral or
// bispectral files are refused where colour is expected; reflectances stay <= 1 bit-exactly in
// float files. The oracles are OIIO reading the files back and an independent reading of their ICC
// profiles.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>

#include "exr_support.h"
#include "imagefile/oiio_compat.h"

namespace fs = std::filesystem;
using e2e::read_json;
using e2e::run;
using e2e::write_image;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_metadata") {}
};

TEST(ColourMetadata, OutputTagsDescribeTheWrittenRgb) {
  Scratch s;
  // An ACEScg input tagged lin_ap1_scene: the previews are in the preview space and say so.
  write_image(s / "acescg.exr", 2, 2, {"R", "G", "B"}, OIIO::TypeFloat, {}, 0.3f,
              [](OIIO::ImageSpec& spec) { spec.attribute("colorInteropID", "lin_ap1_scene"); });
  auto r = run((s / "acescg.exr") + " -o " + (s / "o.exr") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr o = e2e::read_exr(s / "o.exr");
  EXPECT_EQ(o.attributes["colorInteropID"], "lin_rec709_scene");
  EXPECT_EQ(o.attributes["spectralize:colorspace"], "ACEScg");
  // --to-rgb into ACEScg: the AP1 primaries and ACES white, and the interop ID.
  r = run("--to-rgb " + (s / "o.exr") + " -o " + (s / "cg.exr") + " --colorspace ACEScg -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(s / "cg.exr");
  ASSERT_TRUE(in);
  const OIIO::ParamValue* chroma =
      in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(chroma);
  const float* c = static_cast<const float*>(chroma->data());
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(c[i], ap1[i], 1e-5) << i;
  }
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "lin_ap1_scene");
  // Bispectral files are refused, not reduced to their diagonal.
  write_image(s / "bi.exr", 2, 2,
              {"T.500,000000nm", "T.500,000000nm.510,000000nm", "T.510,000000nm"}, OIIO::TypeFloat);
  r = run("--to-rgb " + (s / "bi.exr") + " -o " + (s / "x.exr"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bispectral"), std::string::npos) << r.err;
  // Reflectances stay <= 1 bit-exactly in float output (the grey ramp's white).
  r = run(kImages + "grey_ramp8.png -o " + (s / "g.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr g = e2e::read_exr(s / "g.exr");
  float peak = 0;
  for (const auto& [ch, nm] : e2e::spectral_channels(g, "T."))
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) peak = std::max(peak, g.at(x, y, ch));
  EXPECT_EQ(peak, 1.0f);
}

// An independent reading of an ICC profile: the primaries and white as the profile's chromatic
// adaptation ('chad') maps them back from its D50 colorants, the red tone curve at 0.5, and the
// description.
struct IccRead {
  bool ok = false;
  double xy[8] = {};
  double trc_half = 0;
  std::string description;
};

IccRead read_icc(const std::string& file) {
  IccRead r;
  auto in = OIIO::ImageInput::open(file);
  if (!in) return r;
  const OIIO::ParamValue* p = in->spec().find_attribute("ICCProfile");
  if (!p) return r;
  const auto* d = static_cast<const unsigned char*>(p->data());
  const std::size_t n = p->datasize();
  auto u32 = [&](std::size_t at) {
    return at + 4 <= n ? (std::uint32_t(d[at]) << 24 | std::uint32_t(d[at + 1]) << 16 |
                          std::uint32_t(d[at + 2]) << 8 | d[at + 3])
                       : 0u;
  };
  auto s15 = [&](std::size_t at) { return static_cast<std::int32_t>(u32(at)) / 65536.0; };
  auto tag = [&](const char* sig) -> std::size_t {
    for (std::uint32_t i = 0, count = u32(128); i < count; ++i)
      if (std::memcmp(d + 132 + 12 * i, sig, 4) == 0) return u32(132 + 12 * i + 4);
    return 0;
  };
  const std::size_t chad = tag("chad"), trc = tag("rTRC"), desc = tag("desc");
  if (!chad || !trc || !tag("rXYZ") || !tag("gXYZ") || !tag("bXYZ")) return r;
  double m[9];
  for (int i = 0; i < 9; ++i) m[i] = s15(chad + 8 + 4 * i);
  // The inverse of chad (D50 -> the source white) by cofactors.
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                     m[2] * (m[3] * m[7] - m[4] * m[6]);
  const double inv[9] = {(m[4] * m[8] - m[5] * m[7]) / det, (m[2] * m[7] - m[1] * m[8]) / det,
                         (m[1] * m[5] - m[2] * m[4]) / det, (m[5] * m[6] - m[3] * m[8]) / det,
                         (m[0] * m[8] - m[2] * m[6]) / det, (m[2] * m[3] - m[0] * m[5]) / det,
                         (m[3] * m[7] - m[4] * m[6]) / det, (m[1] * m[6] - m[0] * m[7]) / det,
                         (m[0] * m[4] - m[1] * m[3]) / det};
  auto native_xy = [&](double X, double Y, double Z, double* out) {
    const double x = inv[0] * X + inv[1] * Y + inv[2] * Z, y = inv[3] * X + inv[4] * Y + inv[5] * Z,
                 z = inv[6] * X + inv[7] * Y + inv[8] * Z;
    out[0] = x / (x + y + z);
    out[1] = y / (x + y + z);
  };
  const char* colorants[3] = {"rXYZ", "gXYZ", "bXYZ"};
  for (int i = 0; i < 3; ++i) {
    const std::size_t at = tag(colorants[i]);
    native_xy(s15(at + 8), s15(at + 12), s15(at + 16), r.xy + 2 * i);
  }
  native_xy(0.9642, 1.0, 0.8249, r.xy + 6);  // the PCS white, D50
  if (std::memcmp(d + trc, "curv", 4) == 0 && u32(trc + 8) == 1) {
    r.trc_half = std::pow(0.5, (u32(trc + 12) >> 16) / 256.0);
  } else if (std::memcmp(d + trc, "para", 4) == 0) {
    const int type = static_cast<int>(u32(trc + 8) >> 16);
    double g[5] = {};
    for (int i = 0; i < 5; ++i) g[i] = s15(trc + 12 + 4 * i);
    if (type == 0) r.trc_half = std::pow(0.5, g[0]);
    if (type == 3) r.trc_half = 0.5 >= g[4] ? std::pow(g[1] * 0.5 + g[2], g[0]) : g[3] * 0.5;
  } else {
    return r;
  }
  if (desc && std::memcmp(d + desc, "mluc", 4) == 0) {  // UTF-16BE, the first record
    const std::size_t len = u32(desc + 20), off = u32(desc + 24);
    for (std::size_t i = 0; i + 1 < len && desc + off + i + 1 < n; i += 2)
      r.description += static_cast<char>(d[desc + off + i + 1]);
  }
  r.ok = true;
  return r;
}

// Truth (the guide's "Honest colour tags" (docs/guide/pipeline.md)): every RGB file --to-rgb writes
// says its colour space in what its format holds, read back by OIIO: EXR chromaticities (also for
// encoded spaces) and colorInteropID; TIFF, PNG and JPEG an ICC profile of the space's primaries,
// white and curve; where the format cannot say it (Radiance HDR beyond linear Rec.709, a log curve
// in TIFF) a counted warning names the file and what readers will assume.
TEST(ColourMetadata, EveryFormatSaysItsColourSpace) {
  Scratch s;
  ASSERT_EQ(run(kImages + "grey_ramp8.png -o " + (s / "g.exr") + " -q").exit_code, 0);
  const double rec709[8] = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290};
  const double ap1[8] = {0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767};
  const double adobe[8] = {0.64, 0.33, 0.21, 0.71, 0.15, 0.06, 0.3127, 0.3290};
  struct Case {
    std::string file, args;
    const double* xy;
    double trc_half;  // the curve at 0.5: sRGB's 0.21404, 2^-2.2 or 1/2
    std::string description;
  };
  const Case cases[] = {
      {"o.tif", "--format uint16", rec709, 0.214041, "sRGB - Texture (srgb_rec709_scene)"},
      {"cg.png", "--format uint16 --colorspace ACEScg", ap1, 0.5, "ACEScg (lin_ap1_scene)"},
      {"a.jpg", "--format uint8 --colorspace 'Adobe RGB (1998) - Texture'", adobe,
       std::pow(0.5, 563.0 / 256), "Adobe RGB (1998) - Texture (g22_adobergb_scene)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / c.file) + " " + c.args + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const IccRead icc = read_icc(s / c.file);
    ASSERT_TRUE(icc.ok);
    for (int i = 0; i < 8; ++i) {
      EXPECT_NEAR(icc.xy[i], c.xy[i], 2e-4) << i;
    }
    EXPECT_NEAR(icc.trc_half, c.trc_half, 2e-4);
    EXPECT_EQ(icc.description, c.description);
  }
  // PNG also keeps the interop ID, and with OIIO 2 the config's name. (OIIO 3 reads a PNG's
  // oiio:ColorSpace from its gAMA chunk alone, "lin_rec709_scene" for any linear one: the ICC
  // profile and the interop ID are what say AP1 there.)
  auto in = OIIO::ImageInput::open(s / "cg.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "lin_ap1_scene");
  if (!spectralize::oiio_compat::kInteropColourSpaceNames) {
    EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "ACEScg");
  }
  // An EXR in an encoded space: its primaries' chromaticities and its interop ID.
  ASSERT_EQ(run("--to-rgb " + (s / "g.exr") + " -o " + (s / "s.exr") +
                " --colorspace 'sRGB - Texture' -q")
                .exit_code,
            0);
  in = OIIO::ImageInput::open(s / "s.exr");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "srgb_rec709_scene");
  const auto* chroma =
      in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(chroma);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(static_cast<const float*>(chroma->data())[i], rec709[i], 1e-5) << i;
  }
  // No slot: a warning on stderr and in the report, naming the file and the assumption.
  const std::pair<std::string, std::string> unsaid[] = {
      {"cg.hdr", "--colorspace ACEScg"}, {"log.tif", "--format uint16 --colorspace ACEScct"}};
  for (const auto& [file, args] : unsaid) {
    SCOPED_TRACE(file);
    auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / file) + " " + args + " --report " +
                 (s / "r.json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("WARNING: '" + (s / file) + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("readers will assume"), std::string::npos) << r.err;
    const Json rep = read_json(s / "r.json");
    bool counted = false;
    for (const auto& w : rep["warnings"])
      counted = counted || w.get<std::string>().find("readers will assume") != std::string::npos;
    EXPECT_TRUE(counted) << rep.dump();
  }
  // Linear Rec.709 is what an HDR says: no warning.
  auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / "lin.hdr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("readers will assume"), std::string::npos) << r.err;
}

// A minimal ICC profile with a 'desc' tag (version 2 'desc' type), as cameras and editors embed.
std::vector<unsigned char> icc_profile(const std::string& description) {
  std::vector<unsigned char> p(128, 0);
  auto be32 = [](std::vector<unsigned char>& v, std::uint32_t x) {
    for (int i = 3; i >= 0; --i) v.push_back(static_cast<unsigned char>(x >> (8 * i)));
  };
  be32(p, 1);
  p.insert(p.end(), {'d', 'e', 's', 'c'});
  be32(p, 144);
  be32(p, static_cast<std::uint32_t>(12 + description.size() + 1));
  p.insert(p.end(), {'d', 'e', 's', 'c', 0, 0, 0, 0});
  be32(p, static_cast<std::uint32_t>(description.size() + 1));
  p.insert(p.end(), description.begin(), description.end());
  p.push_back(0);
  return p;
}

TEST(ColourMetadata, ColourMetadataIsHonouredOrNamed) {
  Scratch s;
  const auto with_icc = [](const std::string& desc) {
    return [desc](OIIO::ImageSpec& spec) {
      const auto icc = icc_profile(desc);
      spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, icc.size()), icc.data());
    };
  };
  write_image(s / "adobe.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f,
              with_icc("Adobe RGB (1998)"));
  auto r = run((s / "adobe.jpg") + " -o " + (s / "a.exr") + " --report " + (s / "a.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Json rep = read_json(s / "a.json");
  EXPECT_EQ(rep["colorspace"], "Adobe RGB (1998) - Texture");
  EXPECT_NE(rep["colorspace_reason"].get<std::string>().find("ICC"), std::string::npos);
  write_image(s / "odd.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f,
              with_icc("Wacky Printer 9000"));
  r = run((s / "odd.jpg") + " -o " + (s / "o.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("Wacky Printer 9000"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sRGB - Texture"), std::string::npos) << r.err;  // the space assumed
  // Variants of known profiles have other curves or whites: named, never taken for the standard.
  for (const char* variant : {"sRGB IEC61966-2.1 Linear", "DCI-P3"}) {
    write_image(s / "v.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f, with_icc(variant));
    r = run((s / "v.jpg") + " -o " + (s / "v.exr") + " --report " + (s / "v.json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(variant), std::string::npos) << r.err;
    EXPECT_EQ(read_json(s / "v.json")["colorspace_reason"].get<std::string>().find("ICC"),
              std::string::npos)
        << variant;
  }
  // A linear-tagged PNG (gAMA 1.0): 0.5 stays 0.5 (sRGB decoding would give 0.214).
  write_image(s / "lin.png", 2, 2, {"R", "G", "B"}, OIIO::TypeUInt16, {}, 0.5f,
              [](OIIO::ImageSpec& spec) { spec.attribute("oiio:ColorSpace", "Linear"); });
  r = run((s / "lin.png") + " -o " + (s / "l.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr l = e2e::read_exr(s / "l.exr");
  EXPECT_NEAR(l.at(0, 0, l.channel("G")), 0.5, 1e-3);
  // Channel sets that are not colour are refused, naming the file and the channels.
  write_image(s / "rg.exr", 2, 2, {"R", "G"}, OIIO::TypeFloat);
  write_image(s / "layer.exr", 2, 2, {"diffuse.B", "diffuse.G", "diffuse.R"}, OIIO::TypeFloat);
  for (const char* name : {"rg.exr", "layer.exr"}) {
    r = run((s / name) + " -o " + (s / "x.exr"));
    EXPECT_EQ(r.exit_code, 1) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not an RGB"), std::string::npos) << r.err;
  }
  r = run(kImages + "spectral_samples/colour_D65.exr -o " + (s / "x.exr"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("already a spectral image"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "x.exr"));
}

}  // namespace
