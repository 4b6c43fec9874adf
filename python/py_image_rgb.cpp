#include "py_image_rgb.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "imagefile/image_reader.h"
#include "pipeline/image_report.h"
#include "pipeline/job_plan.h"
#include "py_options.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace py = pybind11;

namespace spectralize::python {

namespace {

// The settings that shape the decision (the rest of an image job's shape its output file).
const OptionScope kReadRgbScope{"read_rgb", 0, {}, {"colorspace", "config", "mode"}};

std::string path_of(const py::handle& v) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::hasattr(v, "__fspath__")) {
    py::object p = py::module_::import("os").attr("fspath")(v);
    if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  }
  throw py::type_error("read_rgb(): path: expected a path (str or os.PathLike), got " +
                       py::str(py::type::of(v).attr("__name__")).cast<std::string>());
}

// spectralize.read_rgb(path, **options)
py::tuple read_rgb(const py::object& path, const py::kwargs& options) {
  const std::string in = path_of(path);
  const Settings asked = read_options(options, kReadRgbScope);
  JobPlan plan;
  try {
    plan = plan_to_spectral(asked, "", OptionNames{"", "output"});
  } catch (const Error& e) {
    value_error(kReadRgbScope, e.what());
  }
  JobPlan decided;
  std::string twin, failure;
  bool file_failure = false;
  int width = 0, height = 0;
  std::vector<float> rgb;
  {
    py::gil_scoped_release release;
    try {
      ImageReader reader(in, 4, /*straight_alpha=*/true);
      decided = planned_input(plan, in, reader.spec());
      const InputInterpretation& how = decided.interpretation;
      if (!how.data_reason.empty())
        throw Error(quoted_path(in) + ": " + how.data_reason +
                    ": not colour, so it has no spectra (give colorspace= to read it as colour)");
      const ColourSpaces& spaces = decided.colour_spaces();
      twin = spaces.linear_twin(how.colorspace);
      if (twin.empty())
        throw Error(quoted_path(in) + ": colour space '" + how.colorspace +
                    "' has no linear, scene-referred space of its primaries in the OCIO config '" +
                    spaces.origin() + "'");
      const OIIO::ImageSpec& spec = reader.spec();
      width = spec.width, height = spec.height;
      const auto n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
      const int nch = spec.nchannels;
      std::vector<float> row(static_cast<std::size_t>(width) * static_cast<std::size_t>(nch));
      rgb.resize(3 * n);
      const std::vector<int>& c = how.channels.colour;
      for (int y = 0; y < height; ++y) {
        reader.read_rows(y, y + 1, row.data());
        float* out = rgb.data() + 3 * static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        for (int x = 0; x < width; ++x)
          for (int k = 0; k < 3; ++k)
            out[3 * x + k] = row[static_cast<std::size_t>(x * nch + c[c.size() == 1 ? 0 : k])];
      }
      // To CIE XYZ and into the linear space of the same primaries, through OCIO.
      if (twin != how.colorspace) {
        spaces.to_xyz(how.colorspace).apply(rgb.data(), n);
        spaces.from_xyz(twin).apply(rgb.data(), n);
      }
    } catch (const FileError& e) {
      failure = e.what();
      file_failure = true;
    } catch (const Error& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) {
    if (file_failure) {
      PyErr_SetString(PyExc_OSError, failure.c_str());
      throw py::error_already_set();
    }
    throw py::value_error("read_rgb(): " + failure);
  }
  py::array_t<float> out({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width),
                          static_cast<py::ssize_t>(3)});
  std::copy(rgb.begin(), rgb.end(), out.mutable_data());
  const InputInterpretation& how = decided.interpretation;
  py::dict info;
  info["colorspace"] = how.colorspace;
  info["colorspace_reason"] = how.colorspace_reason;
  const SpaceIdentity identity = SpaceIdentity::of(*how.facts);
  auto text = [](const std::string& v) { return v.empty() ? py::object(py::none()) : py::str(v); };
  info["colorspace_interop_id"] = text(identity.interop_id);
  info["colorspace_interop_id_source"] = text(identity.interop_id_source);
  info["colorspace_encoding"] = text(identity.encoding);
  info["linear_colorspace"] = twin;
  info["mode"] = decided.settings.spectral.mode == Mode::emission ? "emission" : "reflectance";
  info["mode_reason"] = how.mode_reason;
  info["warnings"] = how.warnings;
  return py::make_tuple(out, info);
}

}  // namespace

void add_image_rgb(py::module_& m) {
  m.def("read_rgb", &read_rgb, py::arg("path"),
        ("read_rgb(path, **options) -> (rgb, info)\n\n"
         "An image's colour as spectralize decides it (anything OpenImageIO reads): its colour\n"
         "space by the CLI's rules (colorspace= when given, else the file's own tags, the\n"
         "config's file rules, the format's convention, the config's roles), converted\n"
         "through OCIO into the linear scene-referred space of the same primaries: rgb\n"
         "(height, width, 3) float32, row 0 at the top. info: colorspace and its reason, its\n"
         "interop ID (with its source: config or measured) and encoding (None where unknown),\n"
         "linear_colorspace (the space of rgb), mode and its reason, warnings. A data map\n"
         "(by its name or colour space) raises ValueError, an unreadable file OSError.\n"
         "What renderer plugins uplift at render time (spectralize.mitsuba). Cost: reading\n"
         "the image, O(pixels).\n\n"
         "Options:\n" +
         options_doc(kReadRgbScope))
            .c_str());
}

}  // namespace spectralize::python
