#include "py_colour_space.h"

#include <pybind11/stl.h>

#include <string>

#include "pipeline/image_report.h"
#include "pipeline/job_plan.h"
#include "py_options.h"
#include "spectralize/core/error.h"

namespace py = pybind11;

namespace spectralize::python {

namespace {

const OptionScope kColourSpaceScope{"colour_space", 0, {}, {"config"}};

// spectralize.colour_space(name, **options)
py::dict colour_space(const std::string& name, const py::kwargs& options) {
  Settings asked = read_options(options, kColourSpaceScope);
  asked.colorspace = name;
  JobPlan plan;
  try {
    plan = plan_to_spectral(asked, "", OptionNames{"", "output"});
  } catch (const Error& e) {
    value_error(kColourSpaceScope, e.what());
  }
  const ColourSpaceFacts& f = *plan.colorspace.facts;
  const SpaceIdentity identity = SpaceIdentity::of(f);
  auto text = [](const std::string& v) { return v.empty() ? py::object(py::none()) : py::str(v); };
  py::dict d;
  d["name"] = f.name;
  d["interop_id"] = text(identity.interop_id);
  d["interop_id_source"] = text(identity.interop_id_source);
  d["encoding"] = text(identity.encoding);
  d["data"] = f.data;
  d["display_referred"] = f.display_referred;
  d["linear"] = f.linear;
  d["chromaticities"] = f.chromaticities ? py::cast(*f.chromaticities) : py::object(py::none());
  return d;
}

}  // namespace

void add_colour_space(py::module_& m) {
  m.def("colour_space", &colour_space, py::arg("name"),
        ("colour_space(name, **options) -> dict\n\n"
         "What is known of a colour space of the OCIO config (a name, alias, role or interop\n"
         "ID), as every command decides it: its canonical name, interop_id (with its source:\n"
         "config or measured) and encoding (None where unknown), data, display_referred,\n"
         "linear, and chromaticities (red, green, blue, white as CIE xy: a known standard's own,\n"
         "else as measured adapted to D65; None for a space without primaries). An unknown or\n"
         "unusable space raises ValueError. Cost: the config's parse (once per config).\n\n"
         "Options:\n" +
         options_doc(kColourSpaceScope))
            .c_str());
}

}  // namespace spectralize::python
