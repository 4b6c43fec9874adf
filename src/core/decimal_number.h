#pragma once
// The one reader of decimal numbers typed by users (--color, --rgb-to-xyz, wavelength grids,
// --curvature, --filter, compression qualities): the same syntax everywhere and a message that
// says what is wrong with the text, not only that it is wrong.

#include <string_view>

namespace spectralize {

/// `text` as a finite decimal number: an optional sign, digits with an optional point, an
/// optional exponent ("0.25", "+2.5e-1", ".5"). Throws Error "'TEXT' " followed by why: "is not
/// a number", "is a hexadecimal number; write it in decimal (0.25)", "is out of the range of a
/// double (about 2.2e-308 to 1.8e308 in size)", "is not a finite number" (inf, nan). Cost:
/// O(length).
double decimal_number(std::string_view text);

}  // namespace spectralize
