// The screen in front of OCIO's file rules (colour/file_rule_screen.h): it passes every path a
// glob rule can match and holds back those none can. Oracle: the rules' expressions as OCIO's
// documentation states them ("^((<pattern>)(\.<extension>))$", the extension's letters without
// case), worked out by hand for each case; the differential check against OCIO itself, over
// the same kinds of rules, is ColourSpace.FileRulesDecideAsOcioDoesForEveryPath.

#include "colour/file_rule_screen.h"

#include <gtest/gtest.h>

namespace spectralize {
namespace {

using Kind = FileRuleText::Kind;

FileRuleScreen screen(std::vector<FileRuleText> rules) {
  rules.push_back({Kind::fallback, "", ""});
  return FileRuleScreen(rules);
}

TEST(FileRuleScreen, PassesWhatAGlobRuleMatchesAndHoldsBackWhatNoneCan) {
  // The shipped config's rules.
  const FileRuleScreen s = screen({{Kind::glob, "*_[sS][rR][gG][bB]*", "*"},
                                   {Kind::glob, "*_[lL][iI][nN][eE][aA][rR]*", "*"},
                                   {Kind::glob, "*", "[hH][dD][rR]"}});
  EXPECT_TRUE(s.may_match("wall_srgb.png"));
  EXPECT_TRUE(s.may_match("lib/wall_SRGB_v2.tif"));
  EXPECT_TRUE(s.may_match("sky.hdr"));
  EXPECT_TRUE(s.may_match("dir/sky.HDR"));
  EXPECT_TRUE(s.may_match("plate_linear.exr"));
  // Only the default rule matches these: OCIO need not be asked.
  EXPECT_FALSE(s.may_match("wall.png"));
  EXPECT_FALSE(s.may_match("lib/brick_albedo.tif"));
  EXPECT_FALSE(s.may_match("srgb.png"));   // no "_" before it
  EXPECT_FALSE(s.may_match("sky.hdri"));   // the extension is anchored at the end
  EXPECT_FALSE(s.may_match("wall_srgb"));  // no dot: no rule's "\." can match
}

TEST(FileRuleScreen, LettersAreComparedWithoutCaseSoNothingOcioMatchesIsHeldBack) {
  const FileRuleScreen s =
      screen({{Kind::glob, "*/textures/*", "png"}, {Kind::glob, "*_acescg_?*", "EXR"}});
  EXPECT_TRUE(s.may_match("lib/textures/brick.png"));
  EXPECT_TRUE(s.may_match("lib/textures/brick.PNG"));  // OCIO: the extension without case
  EXPECT_TRUE(s.may_match("lib/TEXTURES/brick.png"));  // passed; OCIO refuses the pattern's case
  EXPECT_TRUE(s.may_match("shot_acescg_v2.exr"));
  EXPECT_FALSE(s.may_match("shot_acescg_.exr"));  // '?' needs one character
  EXPECT_FALSE(s.may_match("lib/texture/brick.png"));
  EXPECT_FALSE(s.may_match("lib/textures/brick.png.tx"));
}

TEST(FileRuleScreen, WhatItCannotReadItTakesAsAnything) {
  // A backslash is OCIO's expression's escape ("\d" one digit, "\b" no character): any run. A
  // negated or unusual bracket is any one character ("[!a]" matches "A").
  const FileRuleScreen s = screen({{Kind::glob, "map\\d[0-9][!a]x", "tif"}});
  EXPECT_TRUE(s.may_match("map7 1Ax.tif"));
  EXPECT_TRUE(s.may_match("map12345ax.tif"));
  EXPECT_FALSE(s.may_match("map71y.tif"));    // "x" missing
  EXPECT_FALSE(s.may_match("mop7 1yx.tif"));  // "map" missing
  EXPECT_FALSE(s.may_match("mapxyzx.tif"));   // [0-9] needs a digit
}

TEST(FileRuleScreen, RulesItCannotReadPassEverything) {
  // A regex or a ColorSpaceNamePathSearch rule: every path goes to OCIO.
  EXPECT_TRUE(screen({{Kind::other, "", ""}}).may_match("anything"));
  EXPECT_TRUE(screen({{Kind::glob, "*_srgb", "png"}, {Kind::other, "", ""}}).may_match("x"));
  // Only the default rule: nothing to ask OCIO.
  EXPECT_FALSE(screen({}).may_match("wall_srgb.png"));
}

}  // namespace
}  // namespace spectralize
