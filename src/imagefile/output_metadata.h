#pragma once
// Metadata every written image shares: its DateTime (fixed by SOURCE_DATE_EPOCH for byte-stable
// files) and the input attributes worth carrying over.

#include <string>

namespace spectralize {

/// The EXIF DateTime ("YYYY:MM:DD hh:mm:ss", UTC) for written files: SOURCE_DATE_EPOCH when it
/// is a whole number of seconds from 0 to 253402300799 (the year 9999), else now (local time).
/// An unusable SOURCE_DATE_EPOCH is ignored and described in `warning`. Cost: O(1).
std::string output_date_time(std::string& warning);

/// True for an input attribute that describes the image (artist, copyright, camera, ...), not
/// its encoding, its colour (tags are set anew for the written RGB) or spectralize's own.
/// Cost: O(1).
bool carried_over_attribute(const std::string& name);

}  // namespace spectralize
