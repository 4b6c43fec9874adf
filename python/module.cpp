// The spectralize Python module (docs/DESIGN.md §13): NumPy arrays of colours to exact spectra
// and back, and the file jobs of the CLI, with every option of the CLI by its recipe key.
// The work runs without the GIL on OIIO's thread pool; tables are shared by every call of the
// process (and with the persistent cache of `cache=`).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include "imagefile/safe_output.h"
#include "ingest/ingest.h"
#include "ingest/shard.h"
#include "pipeline/colour_array.h"
#include "pipeline/image_job.h"
#include "pipeline/image_report.h"
#include "pipeline/job_plan.h"
#include "pipeline/render_table.h"
#include "pipeline/table_pool.h"
#include "py_arrays.h"
#include "py_colour_space.h"
#include "py_image_rgb.h"
#include "py_interrupt.h"
#include "py_options.h"
#include "py_rt.h"
#include "py_submodules.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectrum_model.h"
#include "spectralize/version.h"

namespace py = pybind11;

namespace spectralize::python {

namespace {

const OptionNames kKeywordNames{"", "output"};

// An image job whose messages name options as this module's keywords ("format float").
// The scopes of the functions' keyword options (one schema: settings/settings.h).
const OptionScope kSpectraScope{
    "spectra", kColor, {"print_format"}, {"method", "cache", "threads"}};
const OptionScope kToRgbScope{"to_rgb", kToRgb, {"format", "compression", "tile"}, {"mode"}};
const OptionScope kConvertScope{"convert", kImage, {}, {}};
const OptionScope kConvertRgbScope{"convert", kToRgb, {}, {}};
const OptionScope kIngestScope{"ingest", kIngest, {}, {}};
const OptionScope kTableScope{"table", kTable, {}, {}};

// Process-wide state: the node tables (shared by every call, saved to `cache=` folders) and the
// colour setups by their settings. Never destroyed: Python may unload modules in any order.
struct State {
  std::mutex mutex;
  // Lookups share the tables; saving them to a cache file (which adopts the file's nodes)
  // must not run during lookups (SpectralTable::adopt_node).
  std::shared_mutex tables;
  TablePool pool;
  std::map<std::string, std::unique_ptr<ColourArrays>> arrays;
};
State& state() {
  static State* s = new State;
  return *s;
}

py::object g_warning;  // spectralize.SpectralizeWarning

void warn(const std::string& message) {
  if (PyErr_WarnEx(g_warning.ptr(), message.c_str(), 2) != 0) throw py::error_already_set();
}

// Messages of a job, kept while the GIL is released and given to Python afterwards.
struct Messages {
  std::mutex mutex;
  std::vector<std::string> warnings;
  LogFn log() {
    return [this](int level, const std::string& m) {
      if (level != 0) return;
      std::lock_guard<std::mutex> lock(mutex);
      warnings.push_back(m);
    };
  }
  void emit() {
    for (const std::string& w : warnings) warn(w);
  }
};

// Raises OSError with a message of the io layer (a file that cannot be read or written).
[[noreturn]] void os_error(const std::string& message) {
  PyErr_SetString(PyExc_OSError, message.c_str());
  throw py::error_already_set();
}

std::string path_text(const py::handle& v, const char* function, const char* name) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::hasattr(v, "__fspath__")) {
    py::object p = py::module_::import("os").attr("fspath")(v);
    if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  }
  throw py::type_error(std::string(function) + "(): " + name + ": expected a path (str or " +
                       "os.PathLike), got " +
                       py::str(py::type::of(v).attr("__name__")).cast<std::string>());
}

// The OCIO config a call uses, as it is now: the file (config=, else $OCIO as set at this call,
// else the shipped one) and its identity on disk (device, inode, size, modification time), so
// that an edited or replaced config, or a changed $OCIO, is loaded again.
std::string config_identity_now(const Settings& s) {
  std::string path = s.config;
  if (path.empty())
    if (const char* env = std::getenv("OCIO"); env && *env) path = env;
  if (path.empty()) return "shipped";
  struct stat st = {};
  if (::stat(path.c_str(), &st) != 0) return path;
  return path + " " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino) + " " +
         std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) + "." +
         std::to_string(st.st_mtim.tv_nsec);
}

// The colour setup for these settings, made once per distinct settings (config, colour space
// and table); ValueError for an unknown colour space or a bad config. The key holds
// every setting of the schema as given and the config's identity now, so no option of a call
// is ever answered by a setup made for other options.
ColourArrays& colour_arrays(const Settings& s, Messages& messages) {
  std::string key = config_identity_now(s);
  for (const SettingSpec& spec : settings_schema())
    key.append("\n").append(spec.key).append("=").append(spec.format(s));
  State& st = state();
  std::lock_guard<std::mutex> lock(st.mutex);
  auto it = st.arrays.find(key);
  if (it != st.arrays.end()) return *it->second;
  try {
    auto arrays = std::make_unique<ColourArrays>(
        plan_colours(s, ColourSubject::colours, kKeywordNames), st.pool, messages.log());
    return *(st.arrays[key] = std::move(arrays));
  } catch (const Error& e) {
    value_error(kSpectraScope, e.what());
  }
}

// The output array: `given` when it fits (float32, C-ordered, writeable, the right shape),
// else a new one.
py::array_t<float> output_array(const py::object& given, const std::vector<py::ssize_t>& shape,
                                std::size_t bands) {
  if (given.is_none()) return new_float_array(shape, bands);
  std::vector<py::ssize_t> want = shape;
  want.back() = static_cast<py::ssize_t>(bands);
  if (!py::isinstance<py::array_t<float>>(given))
    throw py::type_error("spectra(): out: expected a float32 numpy.ndarray");
  auto out = py::reinterpret_borrow<py::array_t<float>>(given);
  if (!(out.flags() & py::array::c_style) || !out.writeable())
    throw py::value_error("spectra(): out: must be C-contiguous and writeable");
  if (std::vector<py::ssize_t>(out.shape(), out.shape() + out.ndim()) != want)
    throw py::value_error("spectra(): out: shape " +
                          py::str(given.attr("shape")).cast<std::string>() + ", expected " +
                          py::str(py::tuple(py::cast(want))).cast<std::string>());
  return out;
}

// Colours per piece of spectra()'s work: Ctrl-C is heard between pieces. The first piece is
// small; each next one is sized from the time the last took, ~50 ms (direct solves of 471 bands
// take ~1000 times longer per colour than table lookups of 81).
constexpr std::size_t kFirstPiece = 1024, kLargestPiece = 1u << 20;

// spectralize.spectra(rgb, out=None, **options)
py::tuple spectra(const py::object& rgb, const py::object& out_given, const py::kwargs& options) {
  const Settings settings = read_options(options, kSpectraScope);
  FloatArray in = read_float_array(rgb, "spectra(): rgb", 3);
  Messages messages;
  ColourArrays& arrays = colour_arrays(settings, messages);
  const std::size_t bands = arrays.bands();
  py::array_t<float> out = output_array(out_given, in.shape, bands);
  // An `out` that shares memory with `rgb` (any overlap, any strides) would be overwritten
  // while it is read: the colours are copied first, so the result is the same as without.
  if (may_share_memory(in.array, out)) {
    py::array_t<float> copy(static_cast<py::ssize_t>(in.array.size()));
    std::memcpy(copy.mutable_data(), in.data,
                sizeof(float) * static_cast<std::size_t>(in.array.size()));
    in.array = copy;
    in.data = copy.data();
  }
  float* o = out.mutable_data();
  PixelCounts counts;
  std::vector<std::string> save_warnings;
  const auto work = [&](const StopFlag* stop) {
    {
      std::shared_lock<std::shared_mutex> lookups(state().tables);
      std::size_t piece = stop ? kFirstPiece : in.rows;
      for (std::size_t b = 0; b < in.rows;) {
        if (stop && *stop) return;
        const std::size_t n = std::min(piece, in.rows - b);
        const auto t0 = std::chrono::steady_clock::now();
        counts.add(arrays.spectra(in.data + b * 3, n, o + b * bands));
        const double took =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        piece = std::clamp<std::size_t>(
            took > 0 ? static_cast<std::size_t>(static_cast<double>(n) * 0.05 / took) : 2 * n, 256,
            std::min(kLargestPiece, 2 * n));
        b += n;
      }
    }
    if (!arrays.settings().cache_dir.empty()) {
      std::unique_lock<std::shared_mutex> saving(state().tables);
      save_warnings = state().pool.save();  // only the tables that grew
    }
  };
  if (in.rows <= kFirstPiece) {
    py::gil_scoped_release release;  // one piece: done before a Ctrl-C would be noticed
    work(nullptr);
  } else if (!run_interruptibly([&](const StopFlag& stop) { work(&stop); })) {
    // KeyboardInterrupt: nothing is returned (`out`, if given, holds a part of the result).
    throw py::error_already_set();
  }
  const WavelengthGrid& grid = arrays.settings().spectral.grid;
  py::array_t<double> wavelengths(static_cast<py::ssize_t>(grid.size()));
  for (std::size_t i = 0; i < grid.size(); ++i) wavelengths.mutable_at(i) = grid[i];
  messages.emit();
  for (const std::string& w : arrays.warnings()) warn("spectra(): " + w);
  for (const std::string& w : count_warnings(counts, "spectra(): rgb", "colours", kKeywordNames))
    warn(w);
  for (const std::string& w : save_warnings) warn(w);
  return py::make_tuple(wavelengths, out);
}

// spectralize.to_rgb(values, wavelengths, **options)
py::array_t<float> to_rgb(const py::object& values, const py::object& wavelengths,
                          const py::kwargs& options) {
  Settings settings = read_options(options, kToRgbScope);
  if (!settings.display.empty() && !settings.colorspace.empty())
    value_error(kToRgbScope, "give colorspace or display, not both");
  if (!settings.view.empty() && settings.display.empty())
    value_error(kToRgbScope, "view needs display");
  const std::vector<double> nm = read_wavelength_array(wavelengths, "to_rgb(): wavelengths");
  if (nm.empty()) throw py::value_error("to_rgb(): wavelengths: an empty array");
  const FloatArray in = read_float_array(values, "to_rgb(): values", nm.size());
  py::array_t<float> out = new_float_array(in.shape, 3);
  float* o = out.mutable_data();
  std::string failure;
  {
    py::gil_scoped_release release;
    try {
      const JobPlan plan = plan_colours(settings, ColourSubject::spectra, kKeywordNames);
      rgb_of_spectra(in.data, in.rows, nm, plan, o, "wavelengths: ");
    } catch (const Error& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) value_error(kToRgbScope, failure);
  return out;
}

// Thrown through a job when its caller was interrupted: the job unwinds, its temporary file
// is removed.
struct Stopped : std::exception {};

// Between strips: stops the job once Ctrl-C has been seen (run_interruptibly).
ProgressFn stops_on(const StopFlag& stop) {
  return [&stop](std::uint64_t, std::uint64_t) {
    if (stop) throw Stopped();
  };
}

py::object json_object(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// spectralize.convert(input, output, to="spectral", **options)
py::object convert(const py::object& input, const py::object& output, const std::string& to,
                   const py::kwargs& options) {
  if (to != "spectral" && to != "rgb")
    throw py::value_error("convert(): to " + quote(to) + " (valid: spectral, rgb)");
  const bool rgb = to == "rgb";
  const OptionScope& scope = rgb ? kConvertRgbScope : kConvertScope;
  const std::string in = path_text(input, "convert", "input");
  const std::string out = path_text(output, "convert", "output");
  std::vector<std::string> given;
  const Settings asked = read_options(options, scope, &given);
  JobPlan plan;
  try {
    const auto is_given = [&](const char* key) {
      return std::find(given.begin(), given.end(), key) != given.end();
    };
    plan = rgb ? plan_to_rgb(asked, out, is_given("format"), is_given("compression"), kKeywordNames)
               : plan_to_spectral(asked, out, kKeywordNames);
  } catch (const Error& e) {
    value_error(scope, e.what());
  }
  Messages messages;
  std::string report, failure;
  const bool finished = run_interruptibly([&](const StopFlag& stop) {
    try {
      report = rgb ? report_json(run_to_rgb_job(plan, in, out, stops_on(stop), messages.log()))
                   : report_json(run_image_job(plan, in, out, stops_on(stop), messages.log(), {}));
    } catch (const Error& e) {
      failure = e.what();
    }
  });
  // KeyboardInterrupt: the job stopped at its next strip and left nothing behind.
  if (!finished) throw py::error_already_set();
  messages.emit();
  if (!failure.empty()) os_error(failure);
  return json_object(report);
}

// spectralize.ingest(sources, output, ...)
py::dict ingest(const py::object& sources, const py::object& output, const py::object& inputs_from,
                const py::object& manifest, bool force, const std::string& shard,
                const py::kwargs& options) {
  IngestRequest request;
  if (py::isinstance<py::str>(sources) || py::hasattr(sources, "__fspath__"))
    request.sources.push_back(path_text(sources, "ingest", "sources"));
  else
    for (const py::handle& s : sources)
      request.sources.push_back(path_text(s, "ingest", "sources"));
  request.destination = path_text(output, "ingest", "output");
  if (!inputs_from.is_none()) request.inputs_from = path_text(inputs_from, "ingest", "inputs_from");
  if (!manifest.is_none()) request.manifest = path_text(manifest, "ingest", "manifest");
  request.force = force;
  if (request.sources.empty() && request.inputs_from.empty())
    value_error(kIngestScope, "give the files, folders or patterns to ingest (or inputs_from)");
  if (!shard.empty()) {
    // The CLI's parser: the same values accepted and refused (ingest/shard.h).
    try {
      const ShardSpec spec = parse_shard(shard);
      request.shard = spec.index;
      request.shards = spec.count;
    } catch (const Error& e) {
      value_error(kIngestScope, std::string("shard ") + e.what());
    }
  }
  std::optional<JobPlan> job;  // planned once: the options checked, the batch's job
  try {
    job = plan_to_spectral(read_options(options, kIngestScope), "", kKeywordNames);
    request.settings = job->settings;
    request.names = kKeywordNames;
  } catch (const Error& e) {
    value_error(kIngestScope, e.what());
  }
  Messages messages;
  IngestSummary summary;
  std::string failure;
  bool ran = false;
  const bool finished = run_interruptibly([&](const StopFlag& stop) {
    try {
      const IngestPlan plan = plan_ingest(request, std::move(job));
      ran = true;
      summary = run_ingest(plan, nullptr, messages.log(), &stop);
    } catch (const Error& e) {
      failure = e.what();
    }
  });
  // The result of what was done, from memory (the manifest may be a stream: never read back).
  const auto result = [&] {
    py::dict d = json_object(ingest_summary_json(summary));
    py::list failures;
    for (const std::string& record : summary.failures) failures.append(json_object(record));
    d["failures"] = failures;
    return d;
  };
  if (!finished) {
    // KeyboardInterrupt, carrying what was done: the batch stopped at its next strip, and its
    // manifest records the files done (a rerun does the rest).
    if (ran && failure.empty()) {
      PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
      PyErr_Fetch(&type, &value, &trace);
      PyErr_NormalizeException(&type, &value, &trace);
      try {
        py::handle e(value);
        e.attr("summary") = result();
        e.attr("args") = py::make_tuple(
            "ingest(): interrupted: " + std::to_string(summary.files()) + " files done, " +
            std::to_string(summary.not_done) + " not done; manifest '" + summary.manifest + "'");
      } catch (...) {
        PyErr_Restore(type, value, trace);
        throw;
      }
      PyErr_Restore(type, value, trace);
    }
    throw py::error_already_set();
  }
  messages.emit();
  if (!failure.empty()) os_error(failure);
  py::dict d = result();
  if (summary.failed > 0)
    warn("ingest(): " + std::to_string(summary.failed) + " of " + std::to_string(summary.files()) +
         " files failed (see 'failures' and the manifest '" + summary.manifest + "')");
  return d;
}

// spectralize.table(output, **options): `spectralize table -o output`, the same bytes.
py::dict table(const py::object& output, const py::kwargs& options) {
  const std::string out = path_text(output, "table", "output");
  const Settings asked = read_options(options, kTableScope);
  JobPlan plan;
  try {
    plan = plan_table(asked, out, kKeywordNames);
  } catch (const Error& e) {
    value_error(kTableScope, e.what());
  }
  Messages messages;
  RenderTable made;
  std::string failure;
  {
    py::gil_scoped_release release;
    try {
      AtomicOutput file(out, {});  // checked before the work
      made = make_render_table(plan, messages.log());
      file.write(made.bytes);
      file.commit();
    } catch (const Error& e) {
      failure = e.what();
    }
  }
  messages.emit();
  if (!failure.empty()) os_error(failure);
  py::dict d;
  d["output"] = out;
  d["colorspace"] = made.colorspace;
  d["mode"] = std::string(to_string(plan.settings.spectral.mode));
  d["model"] = std::string(plan.settings.spectral.model.name());
  d["wavelengths"] = plan.settings.spectral.grid.to_string();
  d["bytes"] = made.bytes.size();
  d["spectra"] = made.spectra;
  d["boundary_cells"] = made.boundary_cells;
  d["seconds"] = made.seconds;
  return d;
}

py::list models() {
  py::list list;
  for (const ModelInfo& m : spectrum_models()) {
    py::dict d;
    d["name"] = std::string(m.name);
    d["summary"] = std::string(m.summary);
    d["default"] = m.name == default_model_name();
    list.append(d);
  }
  return list;
}

const char* const kModuleDoc = R"(Exact RGB-to-spectrum conversion for spectral rendering.

Every spectrum reproduces its colour exactly (relative CIE XYZ error below 1e-5 in float),
is non-negative, and a reflectance stays within 0..1. Colours are converted from any colour
space of an OpenColorIO config (the shipped one, $OCIO, or config=...) through the same
node table and persistent cache (cache=FOLDER) as the spectralize command-line tool.

Functions:
    spectra(rgb, **options)                  RGB array (..., 3) -> (wavelengths, spectra)
    to_rgb(values, wavelengths, **options)   spectra (..., N) -> RGB array (..., 3)
    convert(input, output, to="spectral", **options)
                                             an image file to a spectral OpenEXR, or back
    ingest(sources, output, **options)       a texture library to spectral OpenEXR files
    table(output, **options)                 a render-time table (.spztab) of a colour space
    rt.Table(path).spectra(rgb)              a table's spectra of RGB colours, at table speed
    models()                                 the spectrum models
    colour_space(name)                       what is known of a colour space of the config

Options are the command-line tool's, named by their recipe keys (--emission-basis is
emission_basis=...), with the same validation. Bad options raise ValueError (TypeError for a
value of the wrong type), unreadable or unwritable files OSError; mapped out-of-gamut colours
and other notes are issued as SpectralizeWarning.
)";

}  // namespace

}  // namespace spectralize::python

PYBIND11_MODULE(spectralize, m) {
  using namespace spectralize::python;
  m.doc() = kModuleDoc;
  m.attr("__version__") = SPECTRALIZE_VERSION;
  g_warning = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "spectralize.SpectralizeWarning",
      "Out-of-gamut colours that were mapped, caches that were rebuilt, and other notes.",
      PyExc_UserWarning, nullptr));
  m.attr("SpectralizeWarning") = g_warning;

  m.def("spectra", &spectra, py::arg("rgb"), py::kw_only(), py::arg("out") = py::none(),
        ("spectra(rgb, *, out=None, **options) -> (wavelengths, values)\n\n"
         "The exact spectra of an array of RGB colours of any shape (..., 3), float.\n"
         "Returns wavelengths (N,) in nm (float64) and values (..., N) (float32): emission\n"
         "(mode='emission', the default: colours are light) or reflectance (mode=\n"
         "'reflectance': 0 <= values <= 1). Out-of-gamut colours are mapped and counted in a\n"
         "SpectralizeWarning; NaN or infinite colours raise ValueError. Runs without the GIL\n"
         "on all cores (threads=...). out: a float32 C-ordered array of the result's shape to\n"
         "fill and return instead of a new one (saves the allocation in loops); it may share\n"
         "memory with rgb (the colours are then copied first: the same numbers). Ctrl-C stops\n"
         "the call within a second (KeyboardInterrupt; out then holds a part of the result).\n"
         "Cost: O(colours x N), plus node solves on first use.\n\n"
         "Options:\n" +
         options_doc(kSpectraScope))
            .c_str());
  m.def("to_rgb", &to_rgb, py::arg("values"), py::arg("wavelengths"),
        ("to_rgb(values, wavelengths, **options) -> rgb\n\n"
         "Integrates spectra (..., N) sampled at wavelengths (N,) nm (strictly increasing,\n"
         "any spacing, used as float64) to RGB (..., 3) float32 by the reference integration: "
         "emission with the\n"
         "observer; reflectance (mode='reflectance') under the illuminant, white balanced\n"
         "(reflected='as-lit': the reflected light itself). Cost: O(spectra x N).\n\n"
         "Options:\n" +
         options_doc(kToRgbScope))
            .c_str());
  m.def("convert", &convert, py::arg("input"), py::arg("output"), py::kw_only(),
        py::arg("to") = "spectral",
        ("convert(input, output, *, to='spectral', **options) -> report (dict)\n\n"
         "to='spectral': an RGB image (anything OpenImageIO reads) to a spectral OpenEXR;\n"
         "to='rgb': a spectral OpenEXR (any writer's) back to RGB. Streams in bounded memory;\n"
         "the output appears only when complete; the input is never overwritten. Returns the\n"
         "report the CLI writes with --report. Ctrl-C stops it within a second\n"
         "(KeyboardInterrupt) leaving nothing behind. Cost: O(pixels x N).\n\n"
         "Options (to='spectral'):\n" +
         options_doc(kConvertScope) + "\nOptions (to='rgb'):\n" + options_doc(kConvertRgbScope))
            .c_str());
  m.def("ingest", &ingest, py::arg("sources"), py::arg("output"), py::kw_only(),
        py::arg("inputs_from") = py::none(), py::arg("manifest") = py::none(),
        py::arg("force") = false, py::arg("shard") = "",
        ("ingest(sources, output, *, inputs_from=None, manifest=None, force=False, shard='', "
         "**options) -> summary (dict)\n\n"
         "A texture library (files, folders, glob patterns; or a list file inputs_from) to\n"
         "spectral OpenEXR files under the folder output, as `spectralize ingest` does: a\n"
         "decision per file, up-to-date outputs skipped, a JSON Lines manifest. Returns the\n"
         "counts and the failed files' records ('failures'); a file that fails does not stop\n"
         "the others and does not raise (a SpectralizeWarning counts them). Ctrl-C stops it\n"
         "within a second: KeyboardInterrupt whose .summary is this result for the files done\n"
         "(with 'interrupted' and 'not_done'), and the manifest records them. Cost: the\n"
         "conversions.\n\n"
         "Options:\n" +
         options_doc(kIngestScope))
            .c_str());
  m.def("table", &table, py::arg("output"),
        ("table(output, **options) -> summary (dict)\n\n"
         "The render-time table of exact spectra of a linear colour space (NAME.spztab), as\n"
         "`spectralize table -o NAME.spztab` writes it, byte for byte, for renderers that read it\n"
         "with spectralize/rt.h. mode='reflectance' (the default) or 'emission'. Written\n"
         "atomically. Returns the colour space, mode, model, wavelengths, size in bytes, node\n"
         "spectra, boundary cells and seconds. Cost: a few seconds (every node's solve).\n\n"
         "Options:\n" +
         options_doc(kTableScope))
            .c_str());
  add_rt_module(m);
  add_image_rgb(m);
  add_colour_space(m);
  m.def("models", &models,
        "models() -> list of dicts (name, summary, default): the spectrum models for model=.\n"
        "No arguments. Cost: O(models).");
  add_python_submodules(m);
}
