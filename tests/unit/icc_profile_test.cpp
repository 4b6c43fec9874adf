// ICC profiles made for the integer formats (colour/icc_profile.h, docs/DESIGN.md §9), read back by
// a parser of the ICC format written here from the specification's layout (header fields at
// fixed offsets, the tag table at byte 128, big-endian s15Fixed16 numbers, the XYZ, sf32, mluc,
// curv and para tag types). Oracles: the specification's own numbers (the PCS illuminant D50
// encoded as 0000F6D6 00010000 0000D32D; the sRGB curve's parameters 2.4, 1/1.055,
// 0.055/1.055, 1/12.92, 0.04045 of IEC 61966-2-1), the sRGB profile's published D50-adapted
// colorants, and for other spaces the normalised primary matrix and Bradford adaptation to D50
// derived in tests/unit/test_support.h. A real sRGB profile on the machine
// (/usr/share/color/icc/) is read by the same parser when one is installed.

#include "colour/icc_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

using test::Mat3;

// One s15Fixed16Number step; a value encoded by rounding is within half of it.
constexpr double kFixedStep = 1.0 / 65536.0;

const std::array<float, 8> kRec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// --- A reader of ICC profiles, from the specification's layout ---

struct Tag {
  std::uint32_t offset = 0, size = 0;
};

class Profile {
 public:
  explicit Profile(std::vector<unsigned char> bytes) : b_(std::move(bytes)) {}

  std::size_t size() const { return b_.size(); }
  std::uint32_t u32(std::size_t at) const {
    if (at + 4 > b_.size()) throw std::out_of_range("u32 past the end");
    return (std::uint32_t{b_[at]} << 24) | (std::uint32_t{b_[at + 1]} << 16) |
           (std::uint32_t{b_[at + 2]} << 8) | std::uint32_t{b_[at + 3]};
  }
  std::uint16_t u16(std::size_t at) const {
    if (at + 2 > b_.size()) throw std::out_of_range("u16 past the end");
    return static_cast<std::uint16_t>((b_[at] << 8) | b_[at + 1]);
  }
  double s15(std::size_t at) const { return static_cast<std::int32_t>(u32(at)) * kFixedStep; }
  std::string sig(std::size_t at) const {
    if (at + 4 > b_.size()) throw std::out_of_range("signature past the end");
    return std::string(b_.begin() + static_cast<std::ptrdiff_t>(at),
                       b_.begin() + static_cast<std::ptrdiff_t>(at + 4));
  }
  unsigned char byte(std::size_t at) const { return b_.at(at); }

  // The tag table: a count at 128, then (signature, offset, size) entries of 12 bytes.
  std::map<std::string, Tag> tags() const {
    std::map<std::string, Tag> t;
    const std::uint32_t n = u32(128);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t e = 132 + 12 * static_cast<std::size_t>(i);
      t[sig(e)] = Tag{u32(e + 4), u32(e + 8)};
    }
    return t;
  }
  Tag tag(const std::string& name) const {
    const auto t = tags();
    const auto it = t.find(name);
    if (it == t.end()) throw std::runtime_error("no tag " + name);
    return it->second;
  }
  std::string type_of(const std::string& name) const { return sig(tag(name).offset); }

  // XYZType: 'XYZ ', 4 reserved bytes, then X, Y, Z.
  std::array<double, 3> xyz(const std::string& name) const {
    const Tag t = tag(name);
    if (sig(t.offset) != "XYZ ") throw std::runtime_error(name + " is not an XYZType");
    return {s15(t.offset + 8), s15(t.offset + 12), s15(t.offset + 16)};
  }
  // s15Fixed16ArrayType ('sf32') of 9 numbers, row by row: the chromatic adaptation matrix.
  Mat3 matrix(const std::string& name) const {
    const Tag t = tag(name);
    if (sig(t.offset) != "sf32") throw std::runtime_error(name + " is not an sf32");
    Mat3 m{};
    for (int i = 0; i < 9; ++i) m[i / 3][i % 3] = s15(t.offset + 8 + 4 * i);
    return m;
  }
  // multiLocalizedUnicodeType ('mluc'): records of (language, country, length, offset from the
  // tag's start) of UTF-16BE text; the en/US record (ASCII text only, as written here), or the
  // v2 textDescriptionType ('desc': an ASCII count and string).
  std::string text(const std::string& name) const {
    const Tag t = tag(name);
    const std::string type = sig(t.offset);
    if (type == "desc") {
      const std::uint32_t n = u32(t.offset + 8);
      std::string s(b_.begin() + t.offset + 12, b_.begin() + t.offset + 12 + n);
      while (!s.empty() && s.back() == '\0') s.pop_back();
      return s;
    }
    if (type != "mluc") throw std::runtime_error(name + " is not text");
    const std::uint32_t records = u32(t.offset + 8), record_size = u32(t.offset + 12);
    for (std::uint32_t r = 0; r < records; ++r) {
      const std::size_t e = t.offset + 16 + static_cast<std::size_t>(r) * record_size;
      if (sig(e) != "enUS" && records > 1) continue;
      const std::uint32_t length = u32(e + 4), offset = u32(e + 8);
      std::string s;
      for (std::uint32_t k = 0; k + 1 < length; k += 2) {
        const std::uint16_t unit = u16(t.offset + offset + k);
        if (unit > 0x7F) throw std::runtime_error("not ASCII");
        s.push_back(static_cast<char>(unit));
      }
      while (!s.empty() && s.back() == '\0') s.pop_back();
      return s;
    }
    throw std::runtime_error(name + " has no en/US text");
  }
  // The parametricCurveType ('para') function type and parameters, if it is one.
  bool parametric(const std::string& name, int& function, std::vector<double>& params) const {
    const Tag t = tag(name);
    if (sig(t.offset) != "para") return false;
    function = u16(t.offset + 8);
    static const int counts[] = {1, 3, 4, 5, 7};
    if (function < 0 || function > 4) throw std::runtime_error("unknown para function");
    params.clear();
    for (int i = 0; i < counts[function]; ++i) params.push_back(s15(t.offset + 12 + 4 * i));
    return true;
  }
  // A TRC evaluated at x in [0, 1] by the specification's definitions of curv and para.
  double curve(const std::string& name, double x) const {
    const Tag t = tag(name);
    int f = 0;
    std::vector<double> p;
    if (parametric(name, f, p)) {
      const double g = p[0];
      switch (f) {
        case 0:
          return std::pow(x, g);
        case 1:
          return x >= -p[2] / p[1] ? std::pow(p[1] * x + p[2], g) : 0.0;
        case 2:
          return x >= -p[2] / p[1] ? std::pow(p[1] * x + p[2], g) + p[3] : p[3];
        case 3:
          return x >= p[4] ? std::pow(p[1] * x + p[2], g) : p[3] * x;
        default:
          return x >= p[4] ? std::pow(p[1] * x + p[2], g) + p[5] : p[3] * x + p[6];
      }
    }
    if (sig(t.offset) != "curv") throw std::runtime_error(name + " is not a curve");
    const std::uint32_t n = u32(t.offset + 8);
    if (n == 0) return x;                                        // identity
    if (n == 1) return std::pow(x, u16(t.offset + 12) / 256.0);  // u8Fixed8 gamma
    const double at = x * (n - 1);
    const std::uint32_t i = std::min<std::uint32_t>(static_cast<std::uint32_t>(at), n - 2);
    const double f0 = u16(t.offset + 12 + 2 * i) / 65535.0,
                 f1 = u16(t.offset + 12 + 2 * (i + 1)) / 65535.0;
    return f0 + (at - i) * (f1 - f0);
  }

 private:
  std::vector<unsigned char> b_;
};

Profile made(const std::array<float, 8>& xy, IccTransfer t, const std::string& description) {
  std::vector<unsigned char> bytes = icc_profile(xy, t, description);
  EXPECT_FALSE(bytes.empty());
  return Profile(std::move(bytes));
}

// IEC 61966-2-1's decoding function, written from the standard.
double srgb_eotf(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double max_abs_difference(const Mat3& a, const Mat3& b) {
  double d = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d = std::max(d, std::abs(a[i][j] - b[i][j]));
  return d;
}

// The profile's colorants as the columns of its RGB -> PCS XYZ matrix.
Mat3 colorant_matrix(const Profile& p) {
  const auto r = p.xyz("rXYZ"), g = p.xyz("gXYZ"), b = p.xyz("bXYZ");
  return {{{r[0], g[0], b[0]}, {r[1], g[1], b[1]}, {r[2], g[2], b[2]}}};
}

// --- The header and the tag table ---

TEST(IccProfile, TheHeaderIsAVersion4RgbDisplayProfileWithTheD50Illuminant) {
  const Profile p = made(kRec709, {IccTransfer::srgb}, "sRGB");
  // The declared size is the size, a multiple of 4 (tag data are 4-byte aligned).
  EXPECT_EQ(p.u32(0), p.size());
  EXPECT_EQ(p.size() % 4, 0u);
  EXPECT_GE(p.size(), 128u + 4u);
  EXPECT_EQ(p.byte(8), 4) << "major version";
  EXPECT_EQ(p.sig(12), "mntr");  // display device class
  EXPECT_EQ(p.sig(16), "RGB ");  // data colour space
  EXPECT_EQ(p.sig(20), "XYZ ");  // profile connection space
  EXPECT_EQ(p.sig(36), "acsp");  // the profile file signature
  // The PCS illuminant, exactly the bytes the specification gives for D50.
  EXPECT_EQ(p.u32(68), 0x0000F6D6u);
  EXPECT_EQ(p.u32(72), 0x00010000u);
  EXPECT_EQ(p.u32(76), 0x0000D32Du);
  EXPECT_NEAR(p.s15(68), 0.9642, 0.5 * kFixedStep);
  EXPECT_NEAR(p.s15(76), 0.8249, 0.5 * kFixedStep);
  // A fixed creation date, 2000-01-01 00:00:00 (dateTimeNumber: six big-endian uInt16), so
  // a profile depends on the space alone.
  const std::uint16_t date[6] = {2000, 1, 1, 0, 0, 0};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(p.u16(24 + 2 * i), date[i]) << "date field " << i;
  }
  // The profile ID (bytes 84-99) is zero, "not calculated": no MD5 checksum that the fixed
  // date, set after LittleCMS saved the profile, would make wrong.
  for (int i = 84; i < 100; ++i) {
    EXPECT_EQ(p.byte(i), 0) << "profile ID byte " << i;
  }
}

TEST(IccProfile, TheTagTableHoldsTheMatrixAndCurveTagsInsideTheFile) {
  const Profile p = made(kRec709, {IccTransfer::srgb}, "sRGB");
  const auto tags = p.tags();
  for (const char* required :
       {"desc", "cprt", "wtpt", "rXYZ", "gXYZ", "bXYZ", "rTRC", "gTRC", "bTRC", "chad"})
    EXPECT_TRUE(tags.count(required)) << "missing tag " << required;
  const std::size_t table_end = 132 + 12 * tags.size();
  for (const auto& [name, t] : tags) {
    SCOPED_TRACE(name);
    EXPECT_GE(t.offset, table_end);
    EXPECT_EQ(t.offset % 4, 0u);
    EXPECT_GE(t.size, 12u);
    EXPECT_LE(std::size_t{t.offset} + t.size, p.size());
    // Tags share data only whole (the three TRCs may be one curve), never overlap in part.
    for (const auto& [other, u] : tags) {
      if (other == name || (u.offset == t.offset && u.size == t.size)) continue;
      EXPECT_TRUE(u.offset >= t.offset + t.size || t.offset >= u.offset + u.size)
          << name << " overlaps " << other;
    }
  }
}

TEST(IccProfile, TheDescriptionIsTheGivenText) {
  const std::string description = "spectralize Linear Rec.709 (sRGB) lin_rec709_scene";
  const Profile p = made(kRec709, {IccTransfer::linear}, description);
  EXPECT_EQ(p.text("desc"), description);
  EXPECT_FALSE(p.text("cprt").empty());
  // Another description, another profile; the same arguments, the same bytes.
  EXPECT_NE(icc_profile(kRec709, {IccTransfer::linear}, "other"),
            icc_profile(kRec709, {IccTransfer::linear}, description));
  EXPECT_EQ(icc_profile(kRec709, {IccTransfer::linear}, description),
            icc_profile(kRec709, {IccTransfer::linear}, description));
}

// --- Colorants and white ---

TEST(IccProfile, TheSrgbProfileHasThePublishedColorantsAndTheD50White) {
  const Profile p = made(kRec709, {IccTransfer::srgb}, "sRGB");
  // The sRGB profile's published colorants (Rec.709 primaries, D65 white, Bradford-adapted to
  // D50), to their 4 decimals. Their Z's sum to 0.8251, not D50's 0.8249 (that profile's D65
  // was not exactly (0.3127, 0.3290)): they are matched within 2.5e-4, the exact derivation
  // within 1e-4 below (EverySpaceIsAdaptedToD50ByBradford).
  const double tol = 2.5e-4;
  const auto r = p.xyz("rXYZ"), g = p.xyz("gXYZ"), b = p.xyz("bXYZ");
  const double published[3][3] = {
      {0.4361, 0.2225, 0.0139}, {0.3851, 0.7169, 0.0971}, {0.1431, 0.0606, 0.7141}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r[i], published[0][i], tol) << "rXYZ " << i;
    EXPECT_NEAR(g[i], published[1][i], tol) << "gXYZ " << i;
    EXPECT_NEAR(b[i], published[2][i], tol) << "bXYZ " << i;
  }
  // RGB (1, 1, 1) is the PCS white: the colorants sum to D50 (three rounded numbers each).
  const double d50[3] = {0.9642, 1.0, 0.8249};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r[i] + g[i] + b[i], d50[i], 2 * kFixedStep) << i;
  }
  // Version 4: the media white point of a display profile is the PCS illuminant D50.
  const auto w = p.xyz("wtpt");
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(w[i], d50[i], 0.5 * kFixedStep) << "wtpt " << i;
  }
  // The chromatic adaptation from D65 to D50: Bradford's, derived independently.
  const Mat3 expected = test::bradford(test::d65_white(), Xyz{0.9642, 1.0, 0.8249});
  EXPECT_LT(max_abs_difference(p.matrix("chad"), expected), 1e-4);
}

TEST(IccProfile, EverySpaceIsAdaptedToD50ByBradford) {
  struct Case {
    const char* name;
    std::array<float, 8> xy;
  };
  const Case cases[] = {
      {"sRGB (Rec.709, D65)", kRec709},
      {"ACEScg (AP1, the ACES white)",
       {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f}},
      {"Rec.2020 (D65)", {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f}},
      {"Display P3 (D65)", {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f}},
      {"Rec.709 primaries, a D50 white",
       {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3457f, 0.3585f}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Profile p = made(c.xy, {IccTransfer::gamma, 2.2}, c.name);
    const auto& xy = c.xy;
    const Mat3 npm = test::rgb_to_xyz(xy[0], xy[1], xy[2], xy[3], xy[4], xy[5], xy[6], xy[7]);
    const Mat3 chad = test::bradford(test::xyz_from_xy(xy[6], xy[7]), Xyz{0.9642, 1.0, 0.8249});
    // Each colorant is 3 rounded numbers; the adaptation is LittleCMS's own arithmetic.
    EXPECT_LT(max_abs_difference(colorant_matrix(p), test::matmul(chad, npm)), 1e-4);
    EXPECT_LT(max_abs_difference(p.matrix("chad"), chad), 1e-4);
  }
}

// --- Curves ---

TEST(IccProfile, TheSrgbCurveHasTheStandardsParameters) {
  const Profile p = made(kRec709, {IccTransfer::srgb}, "sRGB");
  for (const char* trc : {"rTRC", "gTRC", "bTRC"}) {
    SCOPED_TRACE(trc);
    int function = -1;
    std::vector<double> params;
    ASSERT_TRUE(p.parametric(trc, function, params)) << "type " << p.type_of(trc);
    // Function type 3: Y = (aX + b)^g for X >= d, Y = cX below.
    EXPECT_EQ(function, 3);
    const double expected[5] = {2.4, 1 / 1.055, 0.055 / 1.055, 1 / 12.92, 0.04045};
    ASSERT_EQ(params.size(), 5u);
    for (int i = 0; i < 5; ++i) {
      EXPECT_NEAR(params[i], expected[i], 0.5 * kFixedStep) << "parameter " << i;
    }
    // The curve is IEC 61966-2-1's, within what five rounded parameters change (1e-4).
    for (int k = 0; k <= 1000; ++k) {
      const double v = k / 1000.0;
      ASSERT_NEAR(p.curve(trc, v), srgb_eotf(v), 1e-4) << "at " << v;
    }
  }
}

TEST(IccProfile, GammaAndLinearCurvesAreThePowerFunctions) {
  for (const double exponent : {1.8, 2.2, 2.4, 2.6}) {
    SCOPED_TRACE(exponent);
    const Profile p = made(kRec709, {IccTransfer::gamma, exponent}, "gamma");
    for (const char* trc : {"rTRC", "gTRC", "bTRC"})
      for (int k = 0; k <= 100; ++k) {
        const double v = k / 100.0;
        ASSERT_NEAR(p.curve(trc, v), std::pow(v, exponent), 1e-4) << trc << " at " << v;
      }
  }
  const Profile linear = made(kRec709, {IccTransfer::linear}, "linear");
  for (const char* trc : {"rTRC", "gTRC", "bTRC"})
    for (int k = 0; k <= 100; ++k) {
      ASSERT_NEAR(linear.curve(trc, k / 100.0), k / 100.0, 1e-6) << trc;
    }
}

// --- What cannot be made ---

TEST(IccProfile, DegeneratePrimariesMakeNoProfile) {
  auto with = [](int index, float value) {
    std::array<float, 8> xy = kRec709;
    xy[static_cast<std::size_t>(index)] = value;
    return xy;
  };
  for (int y = 1; y < 8; y += 2) {
    EXPECT_TRUE(icc_profile(with(y, 0.0f), {IccTransfer::srgb}, "x").empty()) << "y " << y;
    EXPECT_TRUE(icc_profile(with(y, std::numeric_limits<float>::quiet_NaN()), {}, "x").empty())
        << "NaN y " << y;
    EXPECT_TRUE(icc_profile(with(y - 1, std::numeric_limits<float>::infinity()), {}, "x").empty())
        << "infinite x " << y - 1;
  }
  // Three equal primaries span no gamut.
  const std::array<float, 8> same = {0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3127f, 0.3290f};
  EXPECT_TRUE(icc_profile(same, {IccTransfer::linear}, "x").empty());
}

// --- A real sRGB profile, where the machine has one ---

TEST(IccProfile, ARealSrgbProfileHoldsWhatOursHolds) {
  const fs::path dir = "/usr/share/color/icc";
  std::vector<fs::path> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::string name = it->path().filename().string();
    for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (name.find("srgb") != std::string::npos &&
        (name.ends_with(".icc") || name.ends_with(".icm")))
      found.push_back(it->path());
  }
  if (found.empty()) {
    GTEST_SKIP() << "no sRGB profile in " << dir << " (icc-profiles-free)";
  }
  const Profile ours = made(kRec709, {IccTransfer::srgb}, "sRGB");
  for (const fs::path& path : found) {
    SCOPED_TRACE(path.string());
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in),
                                     std::istreambuf_iterator<char>()};
    const Profile real(std::move(bytes));
    if (real.size() < 132 || real.sig(36) != "acsp" || !real.tags().count("rXYZ")) continue;
    // Same colorants (the real one's to its own rounding) and the same curve.
    EXPECT_LT(max_abs_difference(colorant_matrix(real), colorant_matrix(ours)), 2e-4);
    if (real.tags().count("rTRC"))
      for (int k = 0; k <= 100; ++k) {
        EXPECT_NEAR(real.curve("rTRC", k / 100.0), ours.curve("rTRC", k / 100.0), 2e-3);
      }
  }
}

}  // namespace
}  // namespace spectralize
