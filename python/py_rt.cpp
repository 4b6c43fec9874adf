#include "py_rt.h"

#include <OpenImageIO/parallel.h>
#include <pybind11/numpy.h>
// The module's one unit that compiles the evaluator's definitions
// (include/spectralize/rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "py_arrays.h"
#include "py_options.h"

namespace py = pybind11;

namespace spectralize::python {

namespace {

// `threads` as the settings schema reads it (0: all cores, at most 1024), the CLI's rule and
// message: ValueError "function(): threads ...", TypeError for what is not a whole number.
int threads_option(const std::string& function, const py::object& value) {
  py::kwargs given;
  given["threads"] = value;
  return read_options(given, OptionScope{function, 0, {}, {"threads"}}).threads;
}

// A loaded table, shared by the Python object and any thread filling an array.
class RtTable {
 public:
  explicit RtTable(const std::string& path) {
    std::string error;
    if (!table_.load(path.c_str(), &error)) {
      PyErr_SetString(PyExc_OSError, error.c_str());
      throw py::error_already_set();
    }
  }
  const spz::TableView& view() const { return table_.view(); }

  py::array_t<double> wavelengths() const {
    const spz::TableView& t = view();
    py::array_t<double> out(static_cast<py::ssize_t>(t.bands()));
    for (std::size_t k = 0; k < t.bands(); ++k)
      out.mutable_at(k) = t.header().lambda_start + t.header().lambda_step * static_cast<double>(k);
    return out;
  }

  // The spectra of colours (..., 3) at the table's bands or at `wavelengths` (M,): (values
  // (..., M) float32, counts dict). Without the GIL, on `threads` threads (0: all cores).
  py::tuple spectra(const py::handle& rgb, const py::object& wavelengths,
                    const py::object& threads_given) const {
    // The module's checks (py_arrays.h, the settings schema): NaN and infinities are counted,
    // not refused, as a renderer's lookup counts them.
    const FloatArray colours = read_float_array(rgb, "rt.Table.spectra(): rgb", 3, true);
    const int threads = threads_option("rt.Table.spectra", threads_given);
    std::vector<float> nm;
    if (!wavelengths.is_none()) {
      const std::vector<double> w =
          read_wavelength_array(wavelengths, "rt.Table.spectra(): wavelengths");
      if (w.empty()) throw py::value_error("rt.Table.spectra(): wavelengths: an empty array");
      nm.assign(w.begin(), w.end());
    }
    const std::size_t n = colours.rows;
    const std::size_t row = nm.empty() ? view().bands() : nm.size();
    std::vector<py::ssize_t> shape = colours.shape;
    shape.back() = static_cast<py::ssize_t>(row);
    py::array_t<float> out(shape);
    float* dst = out.mutable_data();
    const float* src = colours.data;
    // OIIO's pool, as the module's other array functions: chunks of 4096 colours, each
    // counting into its own tally.
    std::array<std::atomic<std::size_t>, 4> counts{};
    {
      py::gil_scoped_release release;
      OIIO::parallel_for_chunked(
          0, static_cast<int64_t>(n), 4096,
          [&](int64_t begin, int64_t end) {
            const auto a = static_cast<std::size_t>(begin), b = static_cast<std::size_t>(end);
            std::size_t c[4];
            spz::fetch_array(view(), src + 3 * a, b - a, nm.empty() ? nullptr : nm.data(),
                             nm.size(), dst + row * a, nullptr, c);
            for (int k = 0; k < 4; ++k) counts[k] += c[k];
          },
          OIIO::paropt(threads));
    }
    py::dict tally;
    const char* names[4] = {"exact", "mapped", "invalid", "negative"};
    for (int k = 0; k < 4; ++k) tally[names[k]] = counts[k].load();
    return py::make_tuple(out, tally);
  }

  // The blends of colours (..., 3): each colour's spectrum as up to four rows of `samples`
  // and their weights (a light's scale folded in), the samples of those rows at the table's
  // bands, and the counts. What a renderer gathers from on its own arrays.
  py::tuple blend(const py::handle& rgb, const py::object& threads_given) const {
    const FloatArray colours = read_float_array(rgb, "rt.Table.blend(): rgb", 3, true);
    const int threads = threads_option("rt.Table.blend", threads_given);
    const std::size_t n = colours.rows;
    const spz::TableView& t = view();
    const bool reflectance = t.reflectance();
    std::vector<std::uint32_t> vertex(4 * n);
    std::vector<float> weight(4 * n);
    std::array<std::atomic<std::size_t>, 4> counts{};
    const float* src = colours.data;
    {
      py::gil_scoped_release release;
      OIIO::parallel_for_chunked(
          0, static_cast<int64_t>(n), 4096,
          [&](int64_t begin, int64_t end) {
            std::size_t c[4] = {0, 0, 0, 0};
            for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
              spz::Spectrum s;
              const int status = t.fetch(src + 3 * i, s);
              ++c[status == SPZ_EXACT     ? 0
                  : status == SPZ_MAPPED  ? 1
                  : status == SPZ_INVALID ? 2
                                          : 3];
              const float scale = !s.table ? 0.0f : reflectance ? 1.0f : s.scale;
              for (int k = 0; k < 4; ++k) {
                vertex[4 * i + k] = s.table ? s.vertex[k] : 0;
                weight[4 * i + k] = s.weight[k] * scale;
              }
            }
            for (int k = 0; k < 4; ++k) counts[k] += c[k];
          },
          OIIO::paropt(threads));
    }
    // The distinct spectra blended, in order; each colour's rows index them.
    std::vector<std::uint32_t> distinct(vertex);
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    std::vector<py::ssize_t> shape = colours.shape;
    shape.back() = 4;
    py::array_t<std::uint32_t> rows(shape);
    py::array_t<float> weights(shape);
    const std::size_t bands = t.bands();
    py::array_t<float> samples(
        {static_cast<py::ssize_t>(distinct.size()), static_cast<py::ssize_t>(bands)});
    std::uint32_t* r = rows.mutable_data();
    float* w = weights.mutable_data();
    float* out = samples.mutable_data();
    {
      py::gil_scoped_release release;
      OIIO::parallel_for_chunked(
          0, static_cast<int64_t>(4 * n), 1 << 16,
          [&](int64_t begin, int64_t end) {
            for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
              r[i] = static_cast<std::uint32_t>(
                  std::lower_bound(distinct.begin(), distinct.end(), vertex[i]) - distinct.begin());
              w[i] = weight[i];
            }
          },
          OIIO::paropt(threads));
      // A spectrum of one vertex at weight 1 gives that vertex's samples exactly.
      for (std::size_t j = 0; j < distinct.size(); ++j) {
        spz::Spectrum one{};
        one.table = &t;
        for (int k = 0; k < 4; ++k)
          one.vertex[k] = distinct[j], one.weight[k] = k == 0 ? 1.0f : 0.0f;
        one.scale = 1.0f;
        one.flags = ((distinct[j] & SPZ_BOUNDARY_BIT) ? 1u : 0u) | (reflectance ? 2u : 0u);
        spz::samples(one, out + j * bands);
      }
    }
    py::dict tally;
    const char* names[4] = {"exact", "mapped", "invalid", "negative"};
    for (int k = 0; k < 4; ++k) tally[names[k]] = counts[k].load();
    return py::make_tuple(rows, weights, samples, tally);
  }

 private:
  spz::Table table_;
};

}  // namespace

void add_rt_module(py::module_& m) {
  py::module_ rt = m.def_submodule(
      "rt",
      "Render-time tables (.spztab, made by table() or `spectralize table`): the spectra of\n"
      "colours at table speed, by the same evaluator renderers link (libspectralize_rt).");
  py::class_<RtTable, std::shared_ptr<RtTable>>(rt, "Table",
                                                "A loaded render-time table (read-only).")
      .def(py::init<const std::string&>(), py::arg("path"),
           "Table(path): loads and checks a .spztab file (structure and meaning). OSError names\n"
           "the file and the reason. Cost: O(file size).")
      .def_property_readonly(
          "mode",
          [](const RtTable& t) { return t.view().reflectance() ? "reflectance" : "emission"; },
          "'reflectance' or 'emission'. Cost: O(1).")
      .def_property_readonly(
          "colorspace", [](const RtTable& t) { return std::string(t.view().header().colorspace); },
          "The OCIO colour space the table's RGB belongs to. Cost: O(1).")
      .def_property_readonly("wavelengths", &RtTable::wavelengths,
                             "The table's bands in nm, (N,) float64. Cost: O(N).")
      .def_property_readonly(
          "rgb_to_xyz",
          [](const RtTable& t) {
            py::array_t<double> m({3, 3});
            const spz_file_header& h = t.view().header();
            for (py::ssize_t i = 0; i < 9; ++i) m.mutable_at(i / 3, i % 3) = h.rgb_to_xyz[i];
            return m;
          },
          "The colour space's RGB -> CIE XYZ (D65) matrix, (3, 3) float64. Cost: O(1).")
      .def("spectra", &RtTable::spectra, py::arg("rgb"), py::kw_only(),
           py::arg("wavelengths") = py::none(), py::arg("threads") = 0,
           "spectra(rgb, *, wavelengths=None, threads=0) -> (values, counts)\n\n"
           "The spectra of linear RGB colours (..., 3) of the table's colour space, any float\n"
           "dtype (TypeError for integers, strings, complex numbers): values (..., N) float32\n"
           "at the table's N bands, or (..., M) at the M wavelengths given (nm, 1-D). counts:\n"
           "how many colours were exact, mapped (into the gamut), invalid (NaN, infinite: zero\n"
           "spectra) and negative (luminance below 0: zero spectra). Without the GIL, on\n"
           "`threads` threads (0: all cores; at most 1024, as the CLI's --threads). Cost:\n"
           "O(colours x N).")
      .def("blend", &RtTable::blend, py::arg("rgb"), py::kw_only(), py::arg("threads") = 0,
           "blend(rgb, *, threads=0) -> (rows, weights, samples, counts)\n\n"
           "Each colour's spectrum (rgb (..., 3) as in spectra()) as the blend it is: rows\n"
           "(..., 4) uint32 into samples (R, N) float32 (the table's N bands of the R distinct\n"
           "spectra blended) and weights (..., 4) float32 (summing to 1 for a reflectance, to\n"
           "the light's X+Y+Z for a light; 0 for invalid and negative colours), so that the\n"
           "spectrum is sum(weights[k] * samples[rows[k]]), as spectra() gives it to float\n"
           "rounding (a reflectance clamped to 1). For renderers that gather spectra on\n"
           "their own arrays (spectralize.mitsuba). Without the GIL, on `threads` threads\n"
           "(0: all cores; at most 1024). Cost: O(colours log colours + R x N).");
}

}  // namespace spectralize::python
