#pragma once
// Colour spaces by name, converted to CIE XYZ (D65) through an OpenColorIO config. The OCIO
// headers stay in colour_space.cpp; callers see only names and float RGB.

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/xyz.h"

namespace spectralize {

/// A conversion between two colour spaces by OCIO (in float). Copyable, thread-safe to apply.
class ColourTransform {
 public:
  /// Converts `pixels` packed triples in place. Cost: O(pixels).
  void apply(float* rgb, std::size_t pixels) const;
  /// Converts one colour. Cost: O(1) plus OCIO overhead.
  Xyz operator()(double r, double g, double b) const;
  /// Canonical name of the colour space on the RGB side. Cost: O(1).
  const std::string& source() const { return source_; }

 private:
  friend class ColourSpaces;
  std::shared_ptr<const void> processor_;  // OCIO::ConstCPUProcessorRcPtr, type-erased
  std::string source_;
};

class ColourSpaces {
 public:
  /// Loads the config: `explicit_path` if non-empty, else $OCIO if set, else the config shipped
  /// with spectralize (embedded). Throws Error naming the file and OCIO's reason. Cost: config
  /// parse, ~ms.
  static ColourSpaces load(const std::string& explicit_path = "");

  /// Where the config came from, for reports: "shipped", "$OCIO (path)" or the path. Cost: O(1).
  const std::string& origin() const { return origin_; }
  /// The canonical name of a colour space given by name, alias or role (case-insensitive);
  /// throws Error listing the valid names. Cost: O(spaces).
  std::string resolve(std::string_view name) const;
  /// Every colour-space name with its aliases, "Name (alias1, alias2)". Cost: O(spaces).
  std::vector<std::string> describe() const;
  /// A converter from `space` to CIE-XYZ-D65; throws Error for unknown spaces or configs without
  /// an XYZ-D65 space. Cost: OCIO processor build, ~ms (cached by OCIO).
  ColourTransform to_xyz(std::string_view space) const;
  /// A converter from CIE-XYZ-D65 to `space`; throws Error as to_xyz. Cost: as to_xyz.
  ColourTransform from_xyz(std::string_view space) const;

 private:
  ColourTransform transform(std::string_view space, bool to_xyz) const;
  std::shared_ptr<const void> config_;  // OCIO::ConstConfigRcPtr, type-erased
  std::string origin_;
};

/// Name of the shipped default input space. Cost: O(1).
inline constexpr std::string_view kDefaultColourSpace = "Linear Rec.709 (sRGB)";

}  // namespace spectralize
