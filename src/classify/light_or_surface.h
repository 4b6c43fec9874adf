#pragma once
// Light or surface: whether an input's colours are emitted light or a surface's reflectance
// (docs/DESIGN.md §9), decided from every clue in a stated order, never from the sample type
// alone: the command line, the words of the name and of its folders, then the image itself:
// whether its values, decoded from its colour space, exceed white (a surface reflects at most
// what falls on it, so Y > 1 is light), with the aspect of a lat-long map (2:1) noted. One
// function for the single-file command, the OpenImageIO plugin and ingest.

#include <OpenImageIO/imageio.h>

#include <functional>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "settings/map_kind.h"
#include "settings/settings.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

struct ChannelRoles;

/// The brightest pixel of an image, as far as it was read.
struct Brightest {
  double y = 0;           // its luminance Y (CIE XYZ, white Y = 1)
  int row = -1;           // its row (0-based), -1 for an image without finite colour
  bool complete = false;  // every row was read (else reading stopped at a clearly bright pixel)
};

/// Everything the decision looks at. `brightest` is called only when the earlier clues leave
/// the decision open (it reads the image).
struct ModeClues {
  ModeChoice asked = ModeChoice::automatic;  // --mode
  std::string asked_by;                      // who asked, where not --mode (a list's origin)
  NameVerdict name;                          // the file's words, then its folders'
  bool float_data = false;
  bool can_exceed_white = true;  // the colour space decodes values above white (float data,
                                 // or a log space); false: integer data in sRGB, gamma, linear
  std::string colorspace;        // for the reasons
  int width = 0, height = 0;
  // What the file records it holds ("reflectance" or "emission", spectralize:mode): spectralize
  // writes it on RGB it made from spectra, whose kind it knew; "" when the file says nothing.
  std::string recorded_mode;
  std::function<Brightest()> brightest;
};

struct ModeDecision {
  Mode mode = Mode::reflectance;
  std::string reason;
  std::vector<std::string> warnings;  // for people (without the file's name)
};

/// Luminance above which a pixel is light: white (Y = 1) plus a margin for rounding.
inline constexpr double kLightAboveY = 1.001;
/// Up to this peak a light is "barely brighter than white" (warned: a texture with overshoot?).
inline constexpr double kClearlyLightY = 1.5;

/// The decision, first clue that applies: --mode; a light or surface word of the name, else of
/// its folders; the kind the file records (RGB spectralize made from spectra); integer data
/// that cannot exceed white is a surface; else the image's peak: Y
/// above kLightAboveY is light, otherwise a surface (a 2:1 map within white, or a light
/// barely above it, is warned). Cost: O(1) plus brightest() when it is called.
ModeDecision decide_mode(const ModeClues& clues);

/// Reads the colour channels of `file` (level 0 of subimage 0) through `to_xyz` in strips of
/// bounded memory and returns its brightest pixel, stopping early at one above
/// `stop_above_y`. Throws Error naming the file. Cost: decoding the image (less when it stops).
Brightest brightest_pixel(const std::string& file, const ChannelRoles& channels,
                          const ColourTransform& to_xyz, double stop_above_y);

}  // namespace spectralize
