#pragma once
// What a texture map holds, by the words of its name and of its folders (docs/DESIGN.md §9):
// non-colour data (normal, roughness, packed occlusion-roughness-metallic, masks), a surface's
// colour (base colour, albedo) or a light's (emissive maps, HDRIs). One documented table of the
// words the common tools and engines write (Unreal's T_Name_Suffix, Unity, Substance,
// Megascans, USD Preview Surface, MaterialX/Karma, Arnold, their abbreviations), each with
// where in a name it counts; --data-names and --colour-names edit it.

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

/// What a map holds.
enum class MapKind { none, data, reflectance, emission };

/// What a word of the table says. data_if_grey: grey data, colour if RGB (a specular map is a
/// colour in spec/gloss sets and a level in metal/rough ones; Unreal's A is albedo or alpha).
enum class WordKind { data, reflectance, emission, data_if_grey };

/// Where in a name a word counts (the name's last word: the last one that is not a
/// decoration such as 4k, v002, 1001, LOD0, OpenGL, map).
enum class WordPlace {
  anywhere,  // basecolor, roughness, hdri: the map's kind wherever it stands
  last,      // an everyday word too (metal, mask, sky): only as the last word
  engine,    // a letter (N, R, M): only as the last word of an engine-style name, T_Rock_N
  acronym,   // ARM: as engine, or as the last word written in capitals (rock_ARM)
  folder,    // only as a folder's last word (lights/): in a file name it says too little
};

/// One word of the table.
struct NameWord {
  std::string word;  // lower case, letters and digits
  WordKind kind = WordKind::data;
  WordPlace place = WordPlace::anywhere;
  std::string meaning;    // "normal map"
  std::string ambiguity;  // what else it can mean, for warnings ("" if nothing)
};

/// The built-in table (the guide's "In a studio pipeline" (docs/guide/pipeline.md) lists it). Cost:
/// O(1).
std::span<const NameWord> builtin_name_words();

/// Checks an edit of the table as --data-names (`colour` false) or --colour-names takes it:
/// a list replaces the table's words of that kind ("normal,rough"), a list of signed words
/// edits them ("+msk,-metal"); colour words may say ":emission" or ":reflectance" (the
/// default). Returns the canonical text (lower case); throws Error saying what is wrong.
/// Cost: O(length).
std::string check_name_edit(std::string_view text, bool colour);

/// The words in force: the table with the edits of --data-names and --colour-names ("" for
/// none). Words added by a user count anywhere in a name (a letter: as the last word of
/// any name, rock_n). Throws Error as check_name_edit. Cost: O(table).
std::vector<NameWord> name_words_in_force(const std::string& data_edit,
                                          const std::string& colour_edit);

/// One word of a name as written.
struct NameToken {
  std::string text;       // lower case
  bool capitals = false;  // written in capitals, two letters or more ("ARM")
};

/// The words of a name: split at every character that is not a letter or a digit, where a
/// capital follows a lower-case letter (BaseColor), before the last capital of a run that a
/// lower-case letter follows (ORMMap: ORM, Map) and where a digit follows a letter (Rock01);
/// 4k and 16bit stay whole. Cost: O(length).
std::vector<NameToken> name_tokens(std::string_view name);

/// What the name says the map holds, with the reason and the warnings of an ambiguous name.
struct NameVerdict {
  MapKind kind = MapKind::none;
  bool needs_channels = false;  // a data_if_grey word: resolve_by_channels decides
  std::string word;             // the word that decided, as in the table
  std::string reason;           // "name word 'n' of 'T_Rock_N' (engine-style suffix): normal map"
  std::string ambiguity;        // of a needs_channels word, for its warning
  std::vector<std::string> warnings;  // ambiguous words, for people (without the file's name)
};

/// Decides by the file name's words, else by those of its two nearest folders (the parent
/// first); the word that ends last in a name decides (texture names put the map's kind last:
/// metal_plate_basecolor is a colour map), the longer one where two end together. Pure: reads
/// nothing. Cost: O(length x words).
NameVerdict map_kind_by_name(const std::string& path, const std::vector<NameWord>& words);

/// Settles a data_if_grey verdict: grey maps are data, colour maps a surface's colour; warns
/// with the word's ambiguity. Cost: O(1).
void resolve_by_channels(NameVerdict& verdict, bool grey);

/// "data" / "reflectance" / "emission" / "none". Cost: O(1).
std::string_view to_string(MapKind kind);

}  // namespace spectralize
