#pragma once
// The CIE tables of data/, compiled into the library by cmake/EmbedData.cmake.

#include <string_view>
#include <vector>

namespace spectralize::embedded {

struct DataFile {
  std::string_view name;  // file name in data/, e.g. "cie1931_2deg_cmf_1nm.csv"
  std::string_view text;  // the CSV text
};

/// All embedded data files. Cost: O(1).
const std::vector<DataFile>& data_files();

}  // namespace spectralize::embedded
