#include "colour/known_spaces.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace spectralize {

namespace {

// clang-format off
// The standards' own chromaticities, and as a D65-referred config sees them after its Bradford
// adaptation to D65 (measured through OCIO's built-in ACES transforms).
const KnownPrimaries kPrimaries[] = {
    {"rec709",
     {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, kD65x, kD65y},
     {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, kD65x, kD65y}},
    {"rec2020",
     {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, kD65x, kD65y},
     {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, kD65x, kD65y}},
    {"p3d65",
     {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, kD65x, kD65y},
     {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, kD65x, kD65y}},
    {"adobergb",
     {0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, kD65x, kD65y},
     {0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, kD65x, kD65y}},
    {"ap1",
     {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f},
     {0.713196f, 0.292689f, 0.159509f, 0.838789f, 0.128673f, 0.043896f, kD65x, kD65y}},
    {"ap0",
     {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f},
     {0.734855f, 0.264225f, -0.006171f, 1.011315f, 0.015968f, -0.064236f, kD65x, kD65y}},
    {"ciexyzd65",
     {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1 / 3.0f, 1 / 3.0f},
     {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1 / 3.0f, 1 / 3.0f}},
};

// Linear first; Adobe RGB's 563/256 before 2.2 (they differ by 4e-3 at 0.01, more than a
// measured curve's tolerance, so at most one matches).
const KnownEncoding kEncodings[] = {
    {"lin",  {IccTransfer::linear, 1}},
    {"srgb", {IccTransfer::srgb, 2.4}},
    {"g22",  {IccTransfer::gamma, 563.0 / 256}},
    {"g22",  {IccTransfer::gamma, 2.2}},
    {"g24",  {IccTransfer::gamma, 2.4}},
    {"g18",  {IccTransfer::gamma, 1.8}},
    {"g26",  {IccTransfer::gamma, 2.6}},
};

// The interop IDs of the Color Interop Forum that a measurement can tell apart: a transfer
// that is linear, the sRGB curve or a pure gamma, on known primaries, scene- or
// display-referred.
const std::string_view kInteropIds[] = {
    "lin_rec709_scene",   "lin_rec2020_scene",  "lin_p3d65_scene",      "lin_adobergb_scene",
    "lin_ap1_scene",      "lin_ap0_scene",      "lin_ciexyzd65_scene",  "srgb_rec709_scene",
    "g22_rec709_scene",   "g18_rec709_scene",   "srgb_ap1_scene",       "g22_ap1_scene",
    "srgb_p3d65_scene",   "g22_adobergb_scene", "srgb_rec709_display",  "g24_rec709_display",
    "g22_rec709_display", "srgb_p3d65_display", "g22_adobergb_display", "g26_p3d65_display"};

// Names spaces of a known interop ID often have in configs (ACES, the shipped one).
struct UsualNames {
  std::string_view id;
  std::array<std::string_view, 3> names;  // "" pads
};
const UsualNames kUsualNames[] = {
    {"lin_rec709_scene",    {"Linear Rec.709 (sRGB)", "lin_rec709", "Utility - Linear - sRGB"}},
    {"lin_ap1_scene",       {"ACEScg", "ACES - ACEScg", "lin_ap1"}},
    {"lin_ap0_scene",       {"ACES2065-1", "ACES - ACES2065-1", "lin_ap0"}},
    {"lin_rec2020_scene",   {"Linear Rec.2020", "lin_rec2020", "Utility - Linear - Rec.2020"}},
    {"lin_p3d65_scene",     {"Linear P3-D65", "lin_p3d65", ""}},
    {"srgb_rec709_scene",   {"sRGB - Texture", "srgb_tx", "Utility - sRGB - Texture"}},
    {"g22_rec709_scene",    {"Gamma 2.2 Rec.709 - Texture", "g22_rec709_tx", ""}},
    {"g22_adobergb_scene",  {"Adobe RGB (1998) - Texture", "", ""}},
    {"srgb_p3d65_scene",    {"Display P3 - Texture", "", ""}},
    {"srgb_rec709_display", {"sRGB - Display", "srgb_display", ""}},
};
// clang-format on

// Bradford's cone response matrix (Lam 1985), and its inverse.
constexpr double kBradford[3][3] = {
    {0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
constexpr double kBradfordInverse[3][3] = {{0.986992905, -0.147054256, 0.159962652},
                                           {0.43230527, 0.518360272, 0.049291228},
                                           {-0.008528665, 0.040042822, 0.968486696}};

using Vec3 = std::array<double, 3>;

Vec3 mul(const double m[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Vec3 xyz_of_xy(double x, double y) {
  return {x / y, 1.0, (1 - x - y) / y};
}

}  // namespace

double KnownEncoding::operator()(double v) const {
  switch (transfer.kind) {
    case IccTransfer::linear:
      return v;
    case IccTransfer::srgb:
      return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    case IccTransfer::gamma:
      return std::pow(v, transfer.exponent);
  }
  return v;
}

std::span<const KnownPrimaries> known_primaries() {
  return kPrimaries;
}

std::span<const KnownEncoding> known_encodings() {
  return kEncodings;
}

const KnownPrimaries* known_primaries_of(const float* adapted_xy) {
  for (const KnownPrimaries& k : kPrimaries)
    if (chromaticity_difference(k.adapted.data(), adapted_xy) <= kChromaticityTolerance) return &k;
  return nullptr;
}

std::string known_interop_id(std::string_view encoding, std::string_view primaries,
                             bool display_referred) {
  const std::string id = std::string(encoding) + "_" + std::string(primaries) +
                         (display_referred ? "_display" : "_scene");
  for (std::string_view k : kInteropIds)
    if (id == k) return id;
  return "";
}

bool looks_like_interop_id(std::string_view s) {
  if (s == "data") return true;
  const std::size_t first = s.find('_'), last = s.rfind('_');
  if (first == std::string_view::npos || first == 0 || last <= first + 1) return false;
  const std::string_view ref = s.substr(last + 1);
  if (ref != "scene" && ref != "display") return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) ||
          std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
      return false;
  return true;
}

std::span<const std::string_view> usual_names_of(std::string_view interop_id) {
  for (const UsualNames& u : kUsualNames)
    if (u.id == interop_id) {
      const auto n = static_cast<std::size_t>(
          std::find(u.names.begin(), u.names.end(), std::string_view{}) - u.names.begin());
      return std::span<const std::string_view>(u.names.data(), n);
    }
  return {};
}

std::array<float, 8> adapt_chromaticities_to_d65(const float* xy) {
  // RGB -> XYZ of the file's primaries, scaled so that RGB 1 is its white.
  Vec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = xyz_of_xy(xy[2 * i], xy[2 * i + 1]);
  const Vec3 w = xyz_of_xy(xy[6], xy[7]);
  const double det = p[0][0] * (p[1][1] * p[2][2] - p[2][1] * p[1][2]) -
                     p[1][0] * (p[0][1] * p[2][2] - p[2][1] * p[0][2]) +
                     p[2][0] * (p[0][1] * p[1][2] - p[1][1] * p[0][2]);
  std::array<float, 8> out{};
  if (!(std::abs(det) > 1e-12) || !(xy[7] > 0) || !(xy[1] > 0) || !(xy[3] > 0) || !(xy[5] != 0)) {
    for (int i = 0; i < 8; ++i) out[i] = xy[i];
    return out;
  }
  // Scales s with sum_i s_i p_i = w (Cramer's rule).
  auto det3 = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    return a[0] * (b[1] * c[2] - c[1] * b[2]) - b[0] * (a[1] * c[2] - c[1] * a[2]) +
           c[0] * (a[1] * b[2] - b[1] * a[2]);
  };
  const double s[3] = {det3(w, p[1], p[2]) / det, det3(p[0], w, p[2]) / det,
                       det3(p[0], p[1], w) / det};
  // Von Kries in Bradford's cone space, from the white to D65.
  const Vec3 from = mul(kBradford, w), to = mul(kBradford, xyz_of_xy(kD65x, kD65y));
  for (int i = 0; i < 3; ++i) {
    Vec3 c = mul(kBradford, {p[i][0] * s[i], p[i][1] * s[i], p[i][2] * s[i]});
    for (int k = 0; k < 3; ++k) c[k] *= to[k] / from[k];
    const Vec3 a = mul(kBradfordInverse, c);
    const double sum = a[0] + a[1] + a[2];
    out[2 * i] = static_cast<float>(a[0] / sum);
    out[2 * i + 1] = static_cast<float>(a[1] / sum);
  }
  out[6] = kD65x;
  out[7] = kD65y;
  return out;
}

double chromaticity_difference(const float* a, const float* b) {
  double d = 0;
  for (int i = 0; i < 8; ++i) d = std::max(d, std::abs(static_cast<double>(a[i]) - b[i]));
  return d;
}

std::string interop_id_of_chromaticities(const float* xy) {
  const std::array<float, 8> adapted = adapt_chromaticities_to_d65(xy);
  const KnownPrimaries* k = known_primaries_of(adapted.data());
  return k ? std::string("lin_") + std::string(k->id) + "_scene" : "";
}

}  // namespace spectralize
