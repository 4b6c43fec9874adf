#include "colour/icc_profile.h"

#include <lcms2.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace spectralize {

std::vector<unsigned char> icc_profile(const std::array<float, 8>& xy, const IccTransfer& t,
                                       const std::string& description) {
  for (int i = 1; i < 8; i += 2)  // LittleCMS divides by y
    if (!(std::abs(xy[i]) > 1e-6f) || !std::isfinite(xy[i - 1])) return {};
  const cmsCIExyY white{xy[6], xy[7], 1.0};
  const cmsCIExyYTRIPLE primaries{{xy[0], xy[1], 1.0}, {xy[2], xy[3], 1.0}, {xy[4], xy[5], 1.0}};
  cmsToneCurve* curve = nullptr;
  if (t.kind == IccTransfer::srgb) {
    // IEC 61966-2-1: Y = ((X + 0.055) / 1.055)^2.4 above 0.04045, X / 12.92 below.
    const cmsFloat64Number p[5] = {2.4, 1 / 1.055, 0.055 / 1.055, 1 / 12.92, 0.04045};
    curve = cmsBuildParametricToneCurve(nullptr, 4, p);
  } else {
    curve = cmsBuildGamma(nullptr, t.kind == IccTransfer::gamma ? t.exponent : 1.0);
  }
  if (!curve) return {};
  std::unique_ptr<cmsToneCurve, decltype(&cmsFreeToneCurve)> owned_curve(curve, cmsFreeToneCurve);
  cmsToneCurve* curves[3] = {curve, curve, curve};
  cmsHPROFILE profile = cmsCreateRGBProfile(&white, &primaries, curves);
  if (!profile) return {};
  std::unique_ptr<void, decltype(&cmsCloseProfile)> owned(profile, cmsCloseProfile);
  for (cmsTagSignature tag : {cmsSigProfileDescriptionTag, cmsSigCopyrightTag}) {
    cmsMLU* text = cmsMLUalloc(nullptr, 1);
    const std::string value =
        tag == cmsSigProfileDescriptionTag ? description : "No copyright, use freely";
    cmsMLUsetASCII(text, "en", "US", value.c_str());
    cmsWriteTag(profile, tag, text);
    cmsMLUfree(text);
  }
  cmsUInt32Number size = 0;
  if (!cmsSaveProfileToMem(profile, nullptr, &size) || size == 0) return {};
  std::vector<unsigned char> bytes(size);
  if (!cmsSaveProfileToMem(profile, bytes.data(), &size)) return {};
  bytes.resize(size);
  // A profile is a function of the space alone: a fixed creation date (2000-01-01, header bytes
  // 24-35, big-endian) instead of the time of the run keeps outputs reproducible byte for byte.
  const unsigned char date[12] = {0x07, 0xD0, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0};
  if (bytes.size() >= 36) std::copy(date, date + 12, bytes.begin() + 24);
  return bytes;
}

}  // namespace spectralize
