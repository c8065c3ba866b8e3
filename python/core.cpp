// Python bindings, the module spectral_skin._core (re-exported by the package spectral_skin): a
// thin layer over the C++ API that converts types and nothing else. The parameter keywords are
// the parameter table's keys (the CLI flags with underscores, the JSON keys) or the paper's
// symbols, read from parameter_table(); solver= names a model of the transport registry. Results
// are the CLI's JSON documents (src/schema) converted by to_python / stack_to_python
// (document.hpp), holding numpy arrays whose axes are named in the dict's "axes"; what Python adds
// to a document is said where it is added. Parameter keywords may be arrays: they broadcast against each other, every set is
// computed in C++ on all cores (skin::batch) with the GIL released, and the set axes lead the
// result's shape. Units: mm, 1/mm, nm.
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <future>
#include <iterator>
#include <span>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>
#include <type_traits>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "color_fit_schema.hpp"
#include "convert.hpp"
#include "document.hpp"
#include "export_schema.hpp"
#include "fit_schema.hpp"
#include "mc_schema.hpp"
#include "skin/util/allocator.hpp"
#include "skin/batch/batch.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"
#include "skin/fit/fit_many.hpp"
#include "skin/mc/mc.hpp"
#include "skin/export/export.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/work_estimate.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using namespace skin;
using python::Arrays;
using python::Shape;
using python::stack_to_python;
using python::to_python;
using skin::util::Cancelled;
using skin::util::InputError;
using skin::util::WorkEstimate;
using skin::util::check_memory;
using skin::util::estimate_work;
using skin::util::format_number;
using skin::util::one_line;
using skin::util::require_in_range;
using skin::transport::DiffusionStack;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::model::SkinSpectrum;
using skin::model::color_under;
using skin::physics::LayerStack;
using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::Spectrum;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::kDefaultPreset;
using skin::physics::outside_skin_domain;
using skin::physics::parameter_info;
using skin::physics::parameter_table;
using skin::physics::presets;
using skin::physics::skin_layer_stack;

namespace {

Shape concat(Shape a, const Shape& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
py::tuple names(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return py::cast(a);
}

// A new float64 array of `shape` filled by fill(data pointer).
template <class T = double, class F>
py::array_t<T> make_array(const Shape& shape, F&& fill) {
  py::array_t<T> a(shape);
  fill(a.mutable_data());
  return a;
}

[[noreturn]] void not_a_number(std::string_view key, const py::handle& v) {
  throw InputError(std::string(key) + " must be a number, not " + py::cast<std::string>(py::repr(v)));
}

// A number of Python or numpy (not bool: JSON's true is not a number; not text).
double number(std::string_view key, const py::handle& v) {
  if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v) ||
      py::isinstance(v, py::module_::import("numpy").attr("bool_")))
    not_a_number(key, v);
  try {
    return py::cast<double>(v);
  } catch (const py::cast_error&) {
    not_a_number(key, v);
  }
}

// A whole number in [lo, hi]: a Python int or a numpy integer (not bool, not a float, not text).
// Anything else is refused as the command line's options are ("<name> = -1 is out of range:
// must be a whole number >= 1").
long long whole_number(std::string_view name, const py::handle& v, long long lo,
                       long long hi = std::numeric_limits<long long>::max()) {
  const std::string allowed = hi == std::numeric_limits<long long>::max()
                                  ? ">= " + std::to_string(lo)
                                  : "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (py::isinstance<py::bool_>(v) || py::isinstance(v, py::module_::import("numpy").attr("bool_")) ||
      PyIndex_Check(v.ptr()) == 0)
    throw InputError(std::string(name) + " must be a whole number " + allowed + ", not " +
                     py::cast<std::string>(py::repr(v)));
  const py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
  if (!i) throw py::error_already_set();
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (x == -1 && PyErr_Occurred()) throw py::error_already_set();
  if (overflow != 0 || x < lo || x > hi)
    throw InputError(std::string(name) + " = " + py::cast<std::string>(py::str(i)) +
                     " is out of range: must be a whole number " + allowed);
  return x;
}
// Worker threads, as the command line's --threads: 0 (all cores) to 4096.
int thread_count(const py::handle& v) { return static_cast<int>(whole_number("threads", v, 0, 4096)); }

// Runs work() (C++ only: no Python object is touched) on a worker thread with the GIL released,
// while the calling thread looks for Python's signals every 50 ms: on a KeyboardInterrupt (Ctrl-C)
// it requests skin::util::cancel, which the library's loops poll, waits for the work to end (well
// within a second) and raises the KeyboardInterrupt. Work cancelled otherwise (another call's
// interrupt: the flag is the process's) raises KeyboardInterrupt too.
// With `poll` (a progress callback into Python), it is called on the calling thread, with the
// GIL, at each of those looks and once after the work ends; an exception it raises stops the work
// as Ctrl-C does and is raised in its place.
template <class F>
auto interruptible(F&& work, const std::function<void()>& poll = {}) -> decltype(work()) {
  using R = decltype(work());
  std::packaged_task<R()> task(std::forward<F>(work));
  std::future<R> done = task.get_future();
  bool interrupted = false;
  std::optional<py::error_already_set> raised;  // by poll
  {
    py::gil_scoped_release unlocked;
    std::thread worker(std::move(task));
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (interrupted) continue;
      py::gil_scoped_acquire locked;
      if (PyErr_CheckSignals() != 0) {
        interrupted = true;
        util::cancel::request();
        continue;
      }
      if (!poll) continue;
      try {
        poll();
      } catch (py::error_already_set& e) {
        raised.emplace(std::move(e));
        interrupted = true;
        util::cancel::request();
      }
    }
    worker.join();
  }
  if (raised) {
    util::cancel::reset();
    try {
      (void)done.get();
    } catch (...) {
    }
    throw *raised;
  }
  if (interrupted) {
    util::cancel::reset();
    try {
      (void)done.get();  // the work's own end (Cancelled, most likely) gives way to the signal's
    } catch (...) {
    }
    throw py::error_already_set();  // the KeyboardInterrupt (or whatever the handler raised)
  }
  try {
    if constexpr (std::is_void_v<R>) {
      done.get();
      if (poll) poll();
    } else {
      R out = done.get();
      if (poll) poll();
      return out;
    }
  } catch (const Cancelled&) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
}

// batch(first, count) -> std::vector<R> over [0, n) in chunks of kChunkSets sets, polling skin::util::cancel
// between them: batch's functions prepare all their sets before the first is computed (a second
// and more for a million sets), which Ctrl-C would have to wait for.
constexpr std::size_t kChunkSets = 8192;

// A profile call estimated to take this long or more (wavelengths the model solves rather than
// reads) is announced before it starts, with a RuntimeWarning.
constexpr double kAnnouncedSeconds = 10;
constexpr const char* kProgressDoc =
    "progress: None, or a callable progress(done, total) called on the calling thread while the "
    "wavelengths' transport responses are built (total = sets x wavelengths; where a response is "
    "solved rather than read each takes about a second), at most every 50 ms and once at the end; "
    "an exception it raises stops the call and is raised. A call estimated at 10 s or more warns "
    "first (RuntimeWarning, with the estimate). ";

// Says before a long call starts (a RuntimeWarning from kAnnouncedSeconds on) how many of its
// `wavelengths` wavelength profiles the model solves rather than reads, and about how long that takes.
void announce_solves(double solves, std::size_t wavelengths, int threads) {
  const WorkEstimate e = estimate_work(
      format_number(std::round(solves)) + " of the " + std::to_string(wavelengths) +
          " wavelength profiles (off the skin and half-space tables, solved in the frequency domain)",
      solves, model::kProfileSolvesPerSecond, threads, 0);
  if (e.seconds < kAnnouncedSeconds) return;
  const std::string text = e.text + "; progress=callable(done, total) follows it, Ctrl-C stops it";
  if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
}

// A call's progress= (None or a callable, else InputError): the workers count (`count(offset)`
// gives a batch or library callback that raises the count to offset + its own done, in any
// order), and poll() calls the callable on the calling thread, with the GIL (interruptible's
// poll), whenever the count has moved.
class PythonProgress {
 public:
  PythonProgress(const py::object& callable, std::size_t total) : callable_(callable), total_(total) {
    if (!callable.is_none() && !PyCallable_Check(callable.ptr()))
      throw InputError("progress must be a callable progress(done, total) or None, not " +
                       py::cast<std::string>(py::repr(callable)));
  }
  bool wanted() const { return !callable_.is_none(); }
  util::ProgressCallback count(std::size_t offset = 0) {
    if (!wanted()) return {};
    return [this, offset](std::size_t d, std::size_t) {
      std::size_t seen = counted_.load();
      while (offset + d > seen && !counted_.compare_exchange_weak(seen, offset + d)) {
      }
    };
  }
  std::function<void()> poll() {
    if (!wanted()) return {};
    return [this] {
      const std::size_t d = counted_.load();
      if (d == reported_) return;
      reported_ = d;
      callable_(d, total_);
    };
  }

 private:
  py::object callable_;
  std::size_t total_;
  std::atomic<std::size_t> counted_{0};
  std::size_t reported_ = std::numeric_limits<std::size_t>::max();
};
template <class F>
auto in_chunks(std::size_t n, F&& batch) -> decltype(batch(std::size_t{0}, std::size_t{0})) {
  decltype(batch(std::size_t{0}, std::size_t{0})) out;
  out.reserve(n);
  for (std::size_t first = 0; first < n; first += kChunkSets) {
    util::cancel::check();
    auto part = batch(first, std::min(kChunkSets, n - first));
    std::move(part.begin(), part.end(), std::back_inserter(out));
  }
  return out;
}

// The parameter sets of one call: the preset's values overridden by the keywords, broadcast.
struct Sets {
  std::vector<SkinParameters> values;  // row-major over `shape`
  Shape shape;                         // () for one set
  std::vector<std::string> axes;       // name of each axis of `shape`
  std::set<std::string> arrays;        // the keys of the parameters given as arrays
  std::size_t size() const { return values.size(); }
};

// Each keyword: a key of the table, its CLI spelling or the paper's symbol; None leaves the
// preset's value; a number or an array of numbers (not bool, not text). The arrays broadcast
// (numpy's rules) to the sets' shape; an axis is named after the one keyword varying along it
// ("set" when several or none do, "set_<i>" for higher dimensions).
Sets parameter_sets(const std::string& preset, const py::kwargs& kw) {
  const SkinParameters base = find_preset(preset).parameters;
  py::module_ np = py::module_::import("numpy");
  std::map<const ParameterInfo*, std::string> given;  // the keyword each parameter came as
  std::vector<std::pair<const ParameterInfo*, py::array>> arrays;
  for (auto item : kw) {
    const auto name = py::cast<std::string>(item.first);
    const ParameterInfo& info = parameter_info(name);
    if (const auto [it, fresh] = given.emplace(&info, name); !fresh)
      throw InputError(std::string(info.key) + " is given twice: " + it->second + " and " + name +
                       " name the same parameter");
    const py::handle v = item.second;
    if (v.is_none()) continue;
    if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v))
      not_a_number(info.key, v);
    py::array a;
    try {
      a = np.attr("asarray")(v);
    } catch (const py::error_already_set&) {
      not_a_number(info.key, v);
    }
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u' && kind != 'f') not_a_number(info.key, v);
    if (a.size() == 0)
      throw InputError(std::string(info.key) + " is an empty array (shape " +
                       py::cast<std::string>(py::str(a.attr("shape"))) +
                       "): must be a number or an array of numbers with at least one element");
    arrays.emplace_back(&info, np.attr("asarray")(a, "dtype"_a = "float64"));
  }
  Sets s;
  py::list shapes;
  for (const auto& [info, a] : arrays) shapes.append(a.attr("shape"));
  std::vector<py::ssize_t> shape;
  try {
    shape = py::cast<std::vector<py::ssize_t>>(np.attr("broadcast_shapes")(*shapes));
  } catch (const py::error_already_set&) {
    std::string list;
    for (const auto& [info, a] : arrays)
      list += (list.empty() ? "" : ", ") + std::string(info->key) + " " + py::cast<std::string>(py::str(a.attr("shape")));
    throw InputError("the parameter arrays do not broadcast together (numpy's rules): shapes " + list);
  }
  s.shape = shape;
  double sets = 1;
  for (auto d : shape) sets *= static_cast<double>(d);
  check_memory(format_number(sets) + " parameter sets",
               sets * (sizeof(SkinParameters) + 8.0 * static_cast<double>(arrays.size() + parameter_table().size())));
  std::size_t n = 1;
  for (auto d : shape) n *= static_cast<std::size_t>(d);
  s.values.assign(n, base);
  for (const auto& [info, a] : arrays) {
    const auto flat = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
        np.attr("broadcast_to")(a, py::cast(shape)).attr("ravel")());
    for (std::size_t i = 0; i < n; ++i) s.values[i].*(info->member) = flat.data()[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    // Ctrl-C during the checks of a million sets (a fraction of a second with the GIL held)
    if (i % 4096 == 0 && PyErr_CheckSignals() != 0) throw py::error_already_set();
    s.values[i].validate();
  }
  const auto ndim = static_cast<py::ssize_t>(shape.size());
  for (py::ssize_t axis = 0; axis < ndim; ++axis) {
    std::vector<std::string> varying;
    for (const auto& [info, a] : arrays) {
      const py::ssize_t own = a.ndim() - (ndim - axis);
      if (own >= 0 && a.shape(own) > 1) varying.emplace_back(info->key);
    }
    s.axes.push_back(varying.size() == 1 ? varying.front()
                                         : ndim == 1 ? "set" : "set_" + std::to_string(axis));
  }
  if (!shape.empty())
    for (const auto& [info, a] : arrays) s.arrays.emplace(info->key);
  return s;
}

// Which values of one set's document are the same in every set of a call: its names and grids,
// and the parameters not given as arrays (also where the spectrum repeats one).
std::function<bool(std::string_view)> shared_values(const Sets& sets) {
  return [&sets](std::string_view path) {
    for (std::string_view k : {"preset", "solver", "illuminant", "units", "wavelength_nm", "r_mm"})
      if (path == k) return true;
    std::string_view key;
    if (path.starts_with("parameters."))
      key = path.substr(std::string_view("parameters.").size());
    else if (path == "epidermis.thickness_mm")
      key = "epidermis_thickness";
    else
      return false;
    return !sets.arrays.contains(std::string(key));
  };
}

// The axes of the parameters given as arrays: the sets' axes.
void parameter_axes(const Sets& sets, py::dict& axes) {
  for (const ParameterInfo& info : parameter_table())
    if (sets.arrays.contains(std::string(info.key)))
      axes[py::str("parameters." + std::string(info.key))] = names(sets.axes, {});
}

// A RuntimeWarning names the first set outside the model's validated range (as the CLI's one
// warning line does).
void warn_if_invalid(const std::vector<transport::Validity>& v, const transport::Model& model) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!v[i].ok()) {
      std::string text = transport::warning_text(model.name(), v[i]);
      if (v.size() > 1) text = "set " + std::to_string(i) + ": " + text;
      if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
      break;
    }
}

// The validity of a result as Python's has always held it: the command's document leaves out an
// empty reason (valid) and, for one set, an empty outside_skin_domain; Python's has reason ("" when
// valid) and, for arrays of sets, outside_skin_domain (a list per set, empty inside the domain),
// so that every set of an array has one form.
void python_validity(schema::json& validity, bool several_sets) {
  if (!validity.contains("reason")) {  // after "profile", where the document has it when not empty
    schema::json with_reason;
    for (auto it = validity.begin(); it != validity.end(); ++it) {
      with_reason[it.key()] = *it;
      if (it.key() == "profile") with_reason["reason"] = "";
    }
    validity = std::move(with_reason);
  }
  if (several_sets && !validity.contains("outside_skin_domain")) validity["outside_skin_domain"] = schema::json::array();
}

// The parameter keywords, from the table, for the docstrings.
std::string parameter_doc() {
  std::ostringstream os;
  os << "\n\nParameter keywords (a number or an array of numbers; arrays broadcast, one set per "
        "element, computed on all cores; None keeps the preset's value):\n";
  for (const ParameterInfo& p : parameter_table()) {
    os << "  " << p.key;
    if (!p.symbol.empty()) os << " (" << p.symbol << ")";
    os << " [" << p.unit << "] in " << p.range_text() << ", default " << format_number(p.default_value())
       << ": " << p.help << "\n";
  }
  return os.str();
}

std::string solver_doc() {
  std::string s = "solver: a transport model, one of " + transport::model_names_text() + " (default " +
                  std::string(transport::kDefaultModel) + ").";
  return s;
}

// Layers as dicts with the keys of `skin layers --layer` (and of its JSON): sigma_a,
// sigma_s_prime [1/mm], thickness_mm (or thickness; [mm]; absent or None = semi-infinite), eta, g.
LayerStack layer_stack(const std::vector<py::dict>& layers, double eta_above, double eta_below) {
  LayerStack st;
  st.eta_above = eta_above;
  st.eta_below = eta_below;
  if (layers.empty()) throw InputError("layers is empty: give at least one layer (a dict with sigma_a, sigma_s_prime)");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const std::string where = "layer " + std::to_string(i + 1);
    std::vector<std::pair<std::string, std::optional<double>>> entries;
    for (auto [k, v] : layers[i]) {
      if (!py::isinstance<py::str>(k))
        throw InputError(where + ": key " + py::cast<std::string>(py::repr(k)) + " is not a string (" +
                         std::string(python::kLayerKeys) + ")");
      const auto key = py::cast<std::string>(k);
      entries.emplace_back(key, v.is_none() ? std::nullopt : std::optional<double>(number(where + " " + key, v)));
    }
    st.layers.push_back(python::layer_from_entries(entries, i));
  }
  st.validate();
  return st;
}

std::vector<fit::Parameter> free_parameters(const std::optional<std::vector<std::string>>& free,
                                            const std::vector<fit::Parameter>& fallback) {
  if (!free) return fallback;
  std::string list;
  for (const auto& f : *free) list += (list.empty() ? "" : ",") + f;
  return fit::parse_parameter_list(list);
}

std::vector<std::pair<fit::Parameter, fit::Bounds>> fit_bounds(
    const std::map<std::string, std::pair<double, double>>& bounds) {
  std::vector<std::pair<fit::Parameter, fit::Bounds>> out;
  for (const auto& [name, b] : bounds) {
    if (!(b.first < b.second))
      throw InputError("bound = '" + name + "=" + format_number(b.first) + ":" + format_number(b.second) + "': need LO < HI");
    out.emplace_back(fit::parse_parameter(name), fit::Bounds{b.first, b.second});
  }
  return out;
}

// fit_color's srgb: the command line's text 'R,G,B', or any sequence (or array) of three numbers.
std::string srgb_text(const py::object& srgb) {
  if (py::isinstance<py::str>(srgb)) return py::cast<std::string>(srgb);
  const std::string wrong = "srgb = " + one_line(py::cast<std::string>(py::repr(srgb))) +
                            " must be three numbers R,G,B (8-bit sRGB, 0-255): a text 'R,G,B' or a sequence of 3 (N colours: an array of shape (N, 3))";
  if (py::isinstance<py::bytes>(srgb) || py::isinstance<py::bool_>(srgb)) throw InputError(wrong);
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(srgb);
  } catch (const py::error_already_set&) {
    throw InputError(wrong);
  }
  if (a.ndim() != 1 || a.shape(0) != 3) throw InputError(wrong);
  std::string text;
  for (const py::handle item : srgb)  // each a number (not bool, not text)
    text += (text.empty() ? "" : ",") + format_number(number("srgb", item));
  return text;
}


// An array of numbers (dtype integer or float; not bool, complex, text or objects) as float64, or
// nullopt when `value` is none.
std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>> numbers_array(const py::object& value) {
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || py::isinstance<py::bool_>(value))
    return std::nullopt;
  py::module_ np = py::module_::import("numpy");
  py::array a;
  try {
    a = np.attr("asarray")(value);
  } catch (const py::error_already_set&) {  // ragged nested lists
    return std::nullopt;
  }
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'f') return std::nullopt;
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(np.attr("asarray")(a, "dtype"_a = "float64"));
}

std::string shape_text(const py::array& a) { return py::cast<std::string>(py::str(py::cast<py::object>(a).attr("shape"))); }

// fit_spectrum's R: one spectrum (an array of numbers) or N of them (N, samples), one per row.
struct Reflectances {
  std::vector<std::vector<double>> rows;
  bool several = false;
};
Reflectances reflectances(const py::object& R, std::size_t samples) {
  const std::string allowed = "R must be a reflectance spectrum (numbers 0-1, one per wavelength) or N of them, an "
                              "array of shape (N, " + std::to_string(samples) + ") with one spectrum per row, not ";
  const auto a = numbers_array(R);
  if (!a || a->ndim() == 0 || a->ndim() > 2)
    throw InputError(allowed + (a ? "an array of shape " + shape_text(*a)
                                  : one_line(py::cast<std::string>(py::repr(R))).substr(0, 80)));
  Reflectances r;
  const double* v = a->data();
  if (a->ndim() == 1) {
    r.rows.emplace_back(v, v + a->shape(0));
    return r;
  }
  r.several = true;
  if (a->shape(0) == 0)
    throw InputError("R is an empty array (shape " + shape_text(*a) + "): give at least one spectrum");
  if (static_cast<std::size_t>(a->shape(1)) != samples)
    throw InputError("R has shape " + shape_text(*a) + " but wavelength_nm has " + std::to_string(samples) +
                     " values: each row of R is one spectrum, a reflectance per wavelength");
  for (py::ssize_t i = 0; i < a->shape(0); ++i) r.rows.emplace_back(v + i * a->shape(1), v + (i + 1) * a->shape(1));
  return r;
}

// fit_color's targets (linear sRGB, decoded as `skin fit --hex/--srgb` decodes them) and whether
// the call gave several: hex, a text or a sequence of N texts; srgb, a text 'R,G,B', three numbers
// or an array (N, 3) of them (8-bit sRGB, 0-255).
struct ColorTargets {
  std::vector<color::Rgb> rgb;
  bool several = false;
};
ColorTargets color_targets(const py::object& hex, const py::object& srgb) {
  if (hex.is_none() == srgb.is_none()) throw InputError("fit_color: give one target: hex or srgb");
  ColorTargets t;
  if (!hex.is_none()) {
    if (py::isinstance<py::str>(hex)) {
      t.rgb.push_back(fit::parse_hex(py::cast<std::string>(hex)));
      return t;
    }
    const std::string wrong = "hex = " + one_line(py::cast<std::string>(py::repr(hex))).substr(0, 80) +
                              " must be a text RRGGBB or a sequence of them";
    py::array a;
    try {
      a = py::module_::import("numpy").attr("asarray")(hex);
    } catch (const py::error_already_set&) {
      throw InputError(wrong);
    }
    if (a.ndim() == 1 && a.shape(0) == 0) throw InputError("hex is an empty sequence: give at least one colour");
    if (a.ndim() != 1 || a.dtype().kind() != 'U') throw InputError(wrong);
    t.several = true;
    for (py::ssize_t i = 0; i < a.shape(0); ++i) {
      try {
        t.rgb.push_back(fit::parse_hex(py::cast<std::string>(a[py::int_(i)])));
      } catch (const InputError& e) {
        throw InputError("hex[" + std::to_string(i) + "]: " + e.what());
      }
    }
    return t;
  }
  const auto a = py::isinstance<py::str>(srgb) ? std::nullopt : numbers_array(srgb);
  if (!a || a->ndim() != 2) {  // one colour: a text or three numbers (srgb_text says what is wrong)
    t.rgb.push_back(fit::parse_srgb8(srgb_text(srgb)));
    return t;
  }
  t.several = true;
  if (a->shape(1) != 3)
    throw InputError("srgb has shape " + shape_text(*a) + ": N colours are an array of shape (N, 3) (8-bit sRGB, 0-255)");
  if (a->shape(0) == 0) throw InputError("srgb is an empty array (shape " + shape_text(*a) + "): give at least one colour");
  const double* v = a->data();
  for (py::ssize_t i = 0; i < a->shape(0); ++i) {
    std::string text;  // the text of one colour: decoded as srgb='R,G,B' is (the same bits)
    for (py::ssize_t c = 0; c < 3; ++c) {
      const double x = v[i * 3 + c];
      require_in_range("srgb[" + std::to_string(i) + ", " + std::to_string(c) + "]", x, 0.0, 255.0);
      text += (c ? "," : "") + format_number(x);
    }
    t.rgb.push_back(fit::parse_srgb8(text));
  }
  return t;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "Spectral Skin: skin reflectance, profiles and colour from four biophysical "
            "parameters (units: mm, 1/mm, nm). Same names as the C++ API and the `skin` CLI.";
  m.attr("__version__") = SKIN_VERSION;
  skin::util::keep_matrix_memory();  // skin/util/allocator.hpp: the frequency-domain profiles, ~1.8x
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  const std::string params = parameter_doc();
  const std::string default_solver(transport::kDefaultModel);

  m.def("presets", [] {
    // The names of `skin presets --format json`'s presets.
    py::list names;
    for (const schema::json& p : schema::presets_result().document) names.append(to_python(p["name"]));
    return names;
  }, "Names of the paper's parameter sets.");

  m.def("parameters", [] { return to_python(schema::parameters_result().document); },
        "The parameter table, as `skin parameters --format json`: key (the keyword), flag, the "
        "paper's symbol (also accepted as a keyword), unit, min/max (None = unbounded), "
        "min_exclusive/max_exclusive, default, skin_domain (min, max: the range the models are "
        "validated over), help.");

  m.def("solvers", &transport::model_names, "Names of the transport models (solver=), the "
        "default first.");

  // `skin spectrum` and `skin color` for one set or an array of sets.
  auto spectra = [](const std::string& preset, double lambda_min, double lambda_max,
                    double lambda_step, const std::string& solver, const py::object& threads_arg,
                    bool with_spectra, const std::string& illuminant, const py::kwargs& kw) {
    const int threads = thread_count(threads_arg);
    const Sets sets = parameter_sets(preset, kw);
    const WavelengthGrid grid(lambda_min, lambda_max, lambda_step);
    const transport::Model& model = transport::find_model(solver);
    const color::Illuminant& light = color::find_illuminant(illuminant);
    // The five spectra of each set (batch::spectra's) and, with_spectra, their arrays.
    check_memory("the spectra of " + std::to_string(sets.size()) + " parameter sets",
                 static_cast<double>(sets.size()) *
                     (sizeof(SkinSpectrum) + 8.0 * 5 * static_cast<double>(grid.size()) * (with_spectra ? 2 : 1)));
    const std::vector<SkinSpectrum> s = interruptible([&] {
      std::vector<SkinSpectrum> out = in_chunks(sets.size(), [&](std::size_t first, std::size_t count) {
        return batch::spectra(std::span(sets.values).subspan(first, count), grid, model, {threads});
      });
      const color::Colorimetry cm(grid, light);
      for (SkinSpectrum& x : out) x.color = color_under(x, cm);
      return out;
    });
    // The command's documents (skin spectrum, skin color) of every set.
    py::dict d = stack_to_python(
        sets.shape,
        [&](std::size_t i) {
          return with_spectra ? schema::spectrum_document(s[i], preset)
                              : schema::color_document(s[i], preset, s[i].color);
        },
        shared_values(sets));
    // skin spectrum's colour is under D65; its document does not say so, Python's result does.
    if (with_spectra) d["illuminant"] = light.name();
    py::dict axes;
    if (with_spectra) {
      const py::tuple wl = names(sets.axes, {"wavelength_nm"});
      axes["wavelength_nm"] = py::make_tuple("wavelength_nm");
      for (const char* k : {"R_d", "epidermis.sigma_a", "epidermis.sigma_s_prime", "dermis.sigma_a",
                            "dermis.sigma_s_prime"})
        axes[k] = wl;
      if (sets.arrays.contains("epidermis_thickness")) axes["epidermis.thickness_mm"] = names(sets.axes, {});
    }
    axes["color.XYZ"] = names(sets.axes, {"XYZ"});
    axes["color.srgb_linear"] = names(sets.axes, {"channel"});
    axes["color.srgb8"] = names(sets.axes, {"channel"});
    axes["color.hex"] = names(sets.axes, {});
    axes["color.lab"] = names(sets.axes, {"Lab"});
    parameter_axes(sets, axes);
    d["axes"] = axes;
    return d;
  };

  m.def(
      "spectrum",
      [spectra](const std::string& preset, double lambda_min, double lambda_max, double lambda_step,
                const std::string& solver, const py::object& threads, const py::kwargs& kw) {
        return spectra(preset, lambda_min, lambda_max, lambda_step, solver, threads, true,
                       std::string(color::kDefaultIlluminant), kw);
      },
      "preset"_a = std::string(kDefaultPreset), py::kw_only(), "lambda_min"_a = 400.0, "lambda_max"_a = 700.0,
      "lambda_step"_a = 2.0, "solver"_a = default_solver, "threads"_a = py::int_(0),
      ("`skin spectrum`: total diffuse reflectance R_d(lambda), the layers' sigma_a and "
       "sigma_s_prime [1/mm] (epidermis, dermis), the colour under D65 (color: XYZ, srgb_linear, "
       "srgb8, hex, lab) and the parameters used. Wavelengths lambda_min..lambda_max every "
       "lambda_step [nm]; threads: worker threads (0 = all cores). result['axes'] names the axes "
       "of every array (the set axes, then wavelength_nm, channel, ...). " + solver_doc() + params).c_str());

  m.def(
      "color",
      [spectra](const std::string& preset, double lambda_min, double lambda_max, double lambda_step,
                const std::string& solver, const py::object& threads, const std::string& illuminant,
                const py::kwargs& kw) {
        return spectra(preset, lambda_min, lambda_max, lambda_step, solver, threads, false, illuminant, kw);
      },
      "preset"_a = std::string(kDefaultPreset), py::kw_only(), "lambda_min"_a = 400.0, "lambda_max"_a = 700.0,
      "lambda_step"_a = 2.0, "solver"_a = default_solver, "threads"_a = py::int_(0),
      "illuminant"_a = std::string(color::kDefaultIlluminant),
      ("`skin color`: the colour of R_d under a CIE illuminant (illuminant=, as `skin color "
       "--illuminant`; D65 by default; illuminants() lists them) with the CIE 1931 2-degree "
       "observer: XYZ (Y_white = 1), srgb_linear (white-balanced; other than D65 after the "
       "Bradford adaptation to D65), srgb8, hex, lab (CIELAB relative to the illuminant's white), "
       "per set. " + solver_doc() + params).c_str());

  m.def("illuminants", &color::illuminant_names,
        "Names of the CIE illuminants (illuminant=), D65 (the default) first.");

  // `skin profile` (per wavelength or, rgb, per channel) for one set or an array of sets.
  auto profiles = [](bool rgb, const std::string& preset, const std::vector<double>& r_mm,
                     double lambda_min, double lambda_max, double lambda_step,
                     const std::string& solver, const py::object& threads_arg, const py::object& progress,
                     const py::kwargs& kw) {
    const int threads = thread_count(threads_arg);
    const Sets sets = parameter_sets(preset, kw);
    const WavelengthGrid grid(lambda_min, lambda_max, lambda_step);
    const transport::Model& model = transport::find_model(solver);
    if (r_mm.empty()) throw InputError("r_mm is empty: give at least one radius [mm] (increasing, >= 0)");
    PythonProgress reports(progress, sets.size() * grid.size());
    const RadialGrid radii = RadialGrid::from(r_mm);
    // R of every set (channels or wavelengths x radii), held twice (the results, the array).
    check_memory("the profiles of " + std::to_string(sets.size()) + " parameter sets",
                 2.0 * static_cast<double>(sets.size()) * static_cast<double>(rgb ? 3 : grid.size()) *
                     static_cast<double>(radii.size()) * 8.0);
    // Wavelengths the model solves rather than reads: said before a long call starts, as `skin
    // profile` says it on a terminal.
    announce_solves(batch::profile_solves(sets.size(), [&](std::size_t i) { return sets.values[i]; }, grid, model),
                    sets.size() * grid.size(), threads);
    std::vector<batch::RgbProfileResult> by_channel;
    std::vector<batch::SpectralProfileResult> by_wavelength;
    interruptible([&] {
      const std::span<const SkinParameters> all(sets.values);
      auto options = [&](std::size_t first) { return batch::Options{threads, reports.count(first * grid.size())}; };
      if (rgb)
        by_channel = in_chunks(sets.size(), [&](std::size_t first, std::size_t count) {
          return batch::rgb_profiles(all.subspan(first, count), grid, radii, model, options(first));
        });
      else
        by_wavelength = in_chunks(sets.size(), [&](std::size_t first, std::size_t count) {
          return batch::spectral_profiles(all.subspan(first, count), grid, radii, model, options(first));
        });
    }, reports.poll());
    std::vector<transport::Validity> v;
    for (const auto& x : by_channel) v.push_back(x.validity);
    for (const auto& x : by_wavelength) v.push_back(x.validity);
    warn_if_invalid(v, model);
    // The command's documents (skin profile --rgb, skin profile) of every set.
    const std::string solver_name(model.name());
    py::dict d = stack_to_python(
        sets.shape,
        [&](std::size_t i) {
          schema::json j = rgb ? schema::rgb_profile_document(by_channel[i].profile, sets.values[i], preset,
                                                               solver_name, v[i])
                               : schema::spectral_profile_document(by_wavelength[i].profile, sets.values[i],
                                                                   preset, solver_name, v[i]);
          python_validity(j["validity"], !sets.shape.empty());
          return j;
        },
        shared_values(sets));
    py::dict axes;
    axes["r_mm"] = py::make_tuple("r_mm");
    if (rgb) {
      // The command's channel objects {"r": ..., "g": ..., "b": ...} as an axis "channel" after
      // the sets' axes.
      py::module_ np = py::module_::import("numpy");
      const auto channels = [&](const char* key) {
        const py::dict per_channel = d[key];
        return np.attr("stack")(py::make_tuple(per_channel["r"], per_channel["g"], per_channel["b"]),
                                "axis"_a = sets.shape.size());
      };
      d["channel"] = py::make_tuple("r", "g", "b");
      d["R"] = channels("R");
      d["R_d"] = channels("R_d");
      axes["R"] = names(sets.axes, {"channel", "r_mm"});
      axes["R_d"] = names(sets.axes, {"channel"});
    } else {
      axes["wavelength_nm"] = py::make_tuple("wavelength_nm");
      axes["R"] = names(sets.axes, {"wavelength_nm", "r_mm"});
      axes["R_d"] = names(sets.axes, {"wavelength_nm"});
    }
    if (!sets.shape.empty())  // the validity of each set (outside_skin_domain: a list per set)
      for (auto item : py::cast<py::dict>(d["validity"]))
        axes[py::str("validity." + py::cast<std::string>(item.first))] = names(sets.axes, {});
    parameter_axes(sets, axes);
    d["axes"] = axes;
    return d;
  };

  // `rgb_profile` and `profile`: one signature, RGB channels or wavelengths.
  const auto def_profile = [&](const char* name, bool rgb, const std::string& doc) {
    m.def(
        name,
        [profiles, rgb](const std::string& preset, const std::vector<double>& r_mm, double lambda_min,
                        double lambda_max, double lambda_step, const std::string& solver,
                        const py::object& threads, const py::object& progress, const py::kwargs& kw) {
          return profiles(rgb, preset, r_mm, lambda_min, lambda_max, lambda_step, solver, threads, progress, kw);
        },
        "preset"_a = std::string(kDefaultPreset), py::kw_only(), "r_mm"_a, "lambda_min"_a = 400.0, "lambda_max"_a = 700.0,
        "lambda_step"_a = 2.0, "solver"_a = default_solver, "threads"_a = py::int_(0), "progress"_a = py::none(),
        (doc + std::string(kProgressDoc) + solver_doc() + params).c_str());
  };
  def_profile("rgb_profile", true,
              "`skin profile --rgb`: radial profile R(r) [1/mm^2] per linear sRGB channel (r, g, b) at "
              "the radii r_mm [mm] (increasing), the channel totals R_d, whether the profile is in the "
              "model's validated range (validity; a RuntimeWarning says why not; validity.skin_domain: "
              "whether the parameters lie in the skin domain, else outside_skin_domain names them) "
              "and the parameters used. R has the axes (sets..., channel, r_mm). ");
  def_profile("profile", false,
              "`skin profile`: radial profile R(r) [1/mm^2] per wavelength at the radii r_mm [mm] "
              "(increasing), the totals R_d(lambda), validity and the parameters used. R has the axes "
              "(sets..., wavelength_nm, r_mm). ");

  m.def(
      "layers",
      [](const std::vector<py::dict>& layers, const std::vector<double>& r_mm, double eta_above,
         double eta_below, const std::string& solver) {
        const LayerStack st = layer_stack(layers, eta_above, eta_below);
        const transport::Model& model = transport::find_model(solver);
        transport::Totals t;
        std::vector<double> R;
        const RadialGrid radii = RadialGrid::from(r_mm);
        interruptible([&] {
          t = model.totals(st);
          if (!r_mm.empty()) R = ProfileSolver(radii).profile(*model.response(st));
        });
        const transport::Validity v = model.validity(st);
        // The profile's validity matters only where one is computed; the totals' always.
        if (!v.totals || (!r_mm.empty() && !v.profile)) {
          const std::string text = transport::warning_text(model.name(), v);
          if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
        }
        schema::json j =
            schema::layers_result(st, DiffusionStack(st), std::string(model.name()), t, r_mm, R, v).document;
        python_validity(j["validity"], false);
        py::dict d = to_python(j);
        if (r_mm.empty()) {  // no radii: the profile's arrays are empty arrays of numbers (empty lists in JSON)
          py::module_ np = py::module_::import("numpy");
          py::dict profile = d["profile"];
          profile["r_mm"] = np.attr("empty")(0);
          profile["R"] = np.attr("empty")(0);
        }
        d["axes"] = py::dict("profile.r_mm"_a = py::make_tuple("r_mm"), "profile.R"_a = py::make_tuple("r_mm"));
        return d;
      },
      "layers"_a, py::kw_only(), "r_mm"_a = std::vector<double>{}, "eta_above"_a = 1.0,
      "eta_below"_a = 1.0, "solver"_a = default_solver,
      ("`skin layers`: R_d, T_d (per power that entered), R_specular, R(r) [1/mm^2] at r_mm "
       "[mm] (increasing) and the layers with their diffusion quantities (alpha_prime, sigma_tr, "
       "z_r, z_b_top, z_b_bottom, A_top, A_bottom) of a layer stack, top to bottom, each a dict with the keys of "
       "`skin layers --layer`: sigma_a, sigma_s_prime [1/mm], thickness_mm [mm] (absent or None "
       "= semi-infinite, last layer only), eta (1.4), g (0.9); eta_above, eta_below: the media "
       "around it. " + solver_doc()).c_str());

  m.def(
      "mc",
      [](const std::optional<std::vector<py::dict>>& layers, std::optional<double> wavelength,
         const std::optional<std::string>& preset, const py::object& photons, const py::object& seed,
         const py::object& threads, double radius_max, const py::object& bins, double eta_above, double eta_below,
         const py::kwargs& kw) {
        // The same limits as `skin mc`'s options.
        mc::Options o;
        o.photons = static_cast<std::uint64_t>(whole_number("photons", photons, 1));
        o.seed = static_cast<std::uint64_t>(whole_number("seed", seed, 0));
        o.threads = thread_count(threads);
        o.r_max = radius_max;
        o.bins = static_cast<std::size_t>(whole_number("bins", bins, 1, 1000000));
        LayerStack st;
        std::optional<schema::McSkin> skin;
        if (layers && wavelength)
          throw InputError("mc: give either layers or wavelength (with the skin parameters), not both");
        if (layers) {
          if (!kw.empty() || preset)
            throw InputError("mc: skin parameters need wavelength and cannot be combined with layers");
          st = layer_stack(*layers, eta_above, eta_below);
        } else if (wavelength) {
          require_in_range("wavelength", *wavelength, 250.0, 1000.0, "nm");
          const Sets sets = parameter_sets(preset.value_or(std::string(kDefaultPreset)), kw);
          if (!sets.shape.empty()) throw InputError("mc: one parameter set at a time (no arrays)");
          st = skin_layer_stack(sets.values.front(), *wavelength);
          skin = schema::McSkin{preset.value_or(std::string(kDefaultPreset)), sets.values.front(), *wavelength};
        } else {
          throw InputError("mc: give either layers or wavelength (with the skin parameters)");
        }
        // The time estimate of `skin mc` (a pilot on this stack): refused beyond a week, a
        // RuntimeWarning beyond an hour.
        const WorkEstimate estimate = interruptible([&] { return mc::estimate(st, o); });
        if (estimate.long_run()) {
          const std::string text = estimate.text + "; Ctrl-C stops it";
          if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
        }
        const mc::Result r = interruptible([&] { return mc::simulate(st, o); });
        py::dict d = to_python(schema::mc_result(st, r, o.seed, skin).document);
        d["axes"] = py::dict("profile.r_mm"_a = py::make_tuple("r_mm"), "profile.R"_a = py::make_tuple("r_mm"),
                             "profile.R_se"_a = py::make_tuple("r_mm"));
        return d;
      },
      py::kw_only(), "layers"_a = py::none(), "wavelength"_a = py::none(), "preset"_a = py::none(),
      "photons"_a = py::int_(100000), "seed"_a = py::int_(1), "threads"_a = py::int_(0),
      "radius_max"_a = 10.0, "bins"_a = py::int_(200),
      "eta_above"_a = 1.0, "eta_below"_a = 1.0,
      ("`skin mc`: Monte Carlo photon transport (MCML method) in a layer stack (layers= as in "
       "layers(), plus g) or in the skin at one wavelength [nm] (wavelength=, the preset and "
       "parameter keywords). R_d, T_d per power that entered with standard errors (_se), per "
       "incident power (_incident), R(r) [1/mm^2] on `bins` annuli out to radius_max [mm], lost: the "
       "weight of packets ended after the longest path allowed (nearly non-absorbing media); the "
       "layers (with sigma_s) as simulated. The "
       "same seed gives the same numbers for any thread count. As `skin mc`, a pilot estimates the "
       "time: a run over a week is refused (ValueError), one over an hour warned of "
       "(RuntimeWarning); Ctrl-C stops it (KeyboardInterrupt)." + params).c_str());

  // The fits' parameter set, as `skin fit --model` (docs/fit.md).
  static const std::string kModelDoc =
      "model: 'paper' (C_m, beta_m, C_h; the default) or 'extended' (also oxygenation, "
      "epidermis_thickness, dermis_scattering_scale, scattering_scale, and for spectra beta_carotene, "
      "epidermal_hemoglobin, blood_vessel_radius; each kept in its range with a weak prior; free= still chooses the list).";

  m.def(
      "fit_spectrum",
      [](const std::vector<double>& wavelength_nm, const py::object& R, const std::string& preset,
         const std::optional<std::vector<std::string>>& free, bool includes_specular,
         double fit_lambda_min, double fit_lambda_max,
         const std::map<std::string, std::pair<double, double>>& bounds, const std::string& solver,
         const std::string& model, const std::optional<double>& port_radius, const std::optional<double>& beam_radius,
         const py::object& threads, const py::kwargs& kw) {
        const fit::ManyOptions many{thread_count(threads)};
        const Sets sets = parameter_sets(preset, kw);
        if (!sets.shape.empty()) throw InputError("fit_spectrum: the start is one parameter set (no arrays)");
        if (beam_radius && !port_radius) throw InputError("beam_radius: applies to a measurement through a port (port_radius)");
        fit::SpectrumFitOptions opt;
        opt.start = sets.values.front();
        fit::use_fit_model(opt, fit::parse_fit_model(model));
        opt.free = free_parameters(free, opt.free);
        opt.includes_specular = includes_specular;
        opt.lambda_min = fit_lambda_min;
        opt.lambda_max = fit_lambda_max;
        opt.bounds = fit_bounds(bounds);
        opt.model = port_radius ? fit::forward_model_through_port(transport::find_model(solver), *port_radius,
                                                                  beam_radius.value_or(0.0))
                                : fit::forward_model(solver);
        const std::string solver_name(transport::find_model(solver).name());
        const Reflectances r = reflectances(R, wavelength_nm.size());
        std::vector<fit::MeasuredSpectrum> spectra;
        for (std::size_t i = 0; i < r.rows.size(); ++i) {
          // Each row checked under its own name (R[i]), fitted under the one spectrum's.
          if (r.several) fit::validate_spectrum({"R[" + std::to_string(i) + "]", wavelength_nm, r.rows[i]});
          spectra.push_back({"spectrum", wavelength_nm, r.rows[i]});
        }
        const std::vector<fit::FitResult> fits =
            interruptible([&] { return fit::fit_spectra(fit::SpectrumFitter(opt), spectra, many); });
        const auto document = [&](std::size_t i) {
          return schema::spectrum_fit_result(spectra[i], fits[i], solver_name, includes_specular,
                                             port_radius.value_or(0.0), beam_radius.value_or(0.0))
              .document;
        };
        py::dict axes;
        if (!r.several) {
          py::dict d = to_python(document(0));
          d["axes"] = py::dict("fitted.wavelength_nm"_a = py::make_tuple("wavelength_nm"),
                               "fitted.measured"_a = py::make_tuple("wavelength_nm"),
                               "fitted.R"_a = py::make_tuple("wavelength_nm"));
          return d;
        }
        // N spectra: each one's document, its values arrays with the axis "spectrum" first; an
        // uncertainty the single document gives as null (not finite) is NaN.
        py::dict d = stack_to_python(
            Shape{static_cast<py::ssize_t>(spectra.size())},
            [&](std::size_t i) {
              schema::json j = document(i);
              for (auto& u : j["uncertainty"]) if (u.is_null()) u = std::numeric_limits<double>::quiet_NaN();
              return j;
            },
            [](std::string_view path) {
              return path == "input" || path == "solver" || path == "includes_specular" || path == "free" ||
                     path == "port_radius" || path == "beam_radius" ||
                     path == "model" || path == "outside_gamut_rms" || path == "fitted.wavelength_nm";
            });
        const py::tuple one = py::make_tuple("spectrum");
        for (const char* group : {"parameters", "uncertainty", "at_bound"})
          for (auto item : py::cast<py::dict>(d[group])) axes[py::str(std::string(group) + "." + py::cast<std::string>(item.first))] = one;
        for (const char* k : {"rms", "delta_e_2000", "outside_gamut", "specular", "iterations", "starts"}) axes[k] = one;
        axes["fitted.wavelength_nm"] = py::make_tuple("wavelength_nm");
        axes["fitted.measured"] = py::make_tuple("spectrum", "wavelength_nm");
        axes["fitted.R"] = py::make_tuple("spectrum", "wavelength_nm");
        d["axes"] = axes;
        return d;
      },
      "wavelength_nm"_a, "R"_a, "preset"_a = std::string(kDefaultPreset), py::kw_only(), "free"_a = py::none(),
      "includes_specular"_a = false, "fit_lambda_min"_a = 400.0, "fit_lambda_max"_a = 700.0,
      "bounds"_a = std::map<std::string, std::pair<double, double>>{}, "solver"_a = default_solver,
      "model"_a = std::string("paper"), "port_radius"_a = py::none(), "beam_radius"_a = py::none(),
      "threads"_a = py::int_(0),
      ("`skin fit --spectrum`: the parameters whose R_d best matches a measured reflectance R "
       "(0-1) at wavelength_nm [nm] (increasing, covering 450-650 nm). free: parameter keys (or "
       "the paper's symbols) to fit (default melanin, melanin_blend, hemoglobin); the others keep the preset's or the "
       "keywords' values (the start). bounds: {key or symbol: (lo, hi)}. " + kModelDoc + " includes_specular: the "
       "measurement includes the surface reflection. port_radius [mm]: the measurement collects only over a disc "
       "of this radius around the beam (an integrating sphere's sample port, `--port-radius`); beam_radius [mm]: "
       "the light enters evenly over a concentric disc of this radius (default 0, a pencil beam). Returns parameters, uncertainty (one sigma), "
       "at_bound, rms, fitted. "
       "R may hold N spectra, an array (N, len(wavelength_nm)) with one spectrum per row: they are "
       "fitted on all cores (threads: worker threads, 0 = all) with the GIL released, each result "
       "bit for bit the one of fit_spectrum(wavelength_nm, R[i], ...), and returned as one dict "
       "shaped like a single result whose values are arrays with a leading axis of length N "
       "(result['axes'] names it 'spectrum'; fitted.R is (N, samples)); input, solver, "
       "includes_specular, free, model, outside_gamut_rms and fitted.wavelength_nm stay single, and an uncertainty that a "
       "single result gives as None is NaN. " + solver_doc() + params).c_str());

  auto color_fit_options = [](const Sets& sets, const std::optional<std::vector<std::string>>& free,
                              double prior, double weight,
                              const std::map<std::string, std::pair<double, double>>& bounds,
                              const std::string& solver, const std::string& model) {
    if (!sets.shape.empty()) throw InputError("the fixed parameters are one set (no arrays)");
    fit::ColorFitOptions opt;
    opt.start = sets.values.front();
    fit::use_fit_model(opt, fit::parse_fit_model(model));
    // As the command: the extended model's priors are the parameter table's, so a beta_m prior
    // other than the defaults would be dropped without a word.
    if (opt.fit_model == fit::FitModel::extended && (prior != 0.7 || weight != 0.2))
      throw InputError("melanin_blend_prior, melanin_blend_weight: not used by model = 'extended', whose priors "
                       "are the parameter table's (docs/fit.md)");
    opt.free = free_parameters(free, opt.free);
    opt.melanin_blend_prior = prior;
    opt.melanin_blend_weight = weight;
    opt.bounds = fit_bounds(bounds);
    opt.model = fit::forward_model(solver);
    return opt;
  };

  m.def(
      "fit_color",
      [color_fit_options](const py::object& hex, const py::object& srgb, const std::string& preset,
                          const std::optional<std::vector<std::string>>& free, double melanin_blend_prior,
                          double melanin_blend_weight, const std::map<std::string, std::pair<double, double>>& bounds,
                          const std::string& solver, const std::string& model, const py::object& threads,
                          const py::kwargs& kw) {
        const fit::ManyOptions many{thread_count(threads)};
        const ColorTargets targets = color_targets(hex, srgb);
        const fit::ColorFitOptions opt = color_fit_options(parameter_sets(preset, kw), free, melanin_blend_prior,
                                                           melanin_blend_weight, bounds, solver, model);
        const std::vector<fit::ColorFitResult> fits =
            interruptible([&] { return fit::fit_colors(fit::ColorFitter(opt), targets.rgb, many); });
        const auto document = [&](std::size_t i) {
          return schema::color_fit_result(fits[i], targets.rgb[i], melanin_blend_prior, melanin_blend_weight).document;
        };
        // (In a batch an uncertainty the single document gives as null, not finite, is NaN.)
        const auto batch_document = [&](std::size_t i) {
          schema::json j = document(i);
          if (j.contains("uncertainty"))
            for (auto& u : j["uncertainty"]) if (u.is_null()) u = std::numeric_limits<double>::quiet_NaN();
          return j;
        };
        // One colour: the command's document with its arrays as lists (as fit_color has always
        // returned it).
        if (!targets.several) return to_python(document(0), Arrays::lists);
        // N colours: each one's document, its values arrays with the axis "target" first.
        py::dict d = stack_to_python(Shape{static_cast<py::ssize_t>(fits.size())}, batch_document, [](std::string_view path) {
          return path == "melanin_blend_prior" || path == "melanin_blend_weight" || path == "model" ||
                 path == "free";
        });
        py::dict axes;
        const py::tuple one = py::make_tuple("target");
        for (const ParameterInfo& info : parameter_table()) axes[py::str("parameters." + std::string(info.key))] = one;
        for (const char* group : {"uncertainty", "at_bound"})
          if (d.contains(group))
            for (auto item : py::cast<py::dict>(d[group]))
              axes[py::str(std::string(group) + "." + py::cast<std::string>(item.first))] = one;
        for (const char* k : {"target.hex", "fitted.hex", "delta_e_2000", "outside_gamut"}) axes[k] = one;
        axes["target.lab"] = py::make_tuple("target", "Lab");
        axes["fitted.lab"] = py::make_tuple("target", "Lab");
        axes["fitted.srgb_linear"] = py::make_tuple("target", "channel");
        d["axes"] = axes;
        return py::object(d);
      },
      py::kw_only(), "hex"_a = py::none(), "srgb"_a = py::none(), "preset"_a = std::string(kDefaultPreset),
      "free"_a = py::none(), "melanin_blend_prior"_a = 0.7, "melanin_blend_weight"_a = 0.2,
      "bounds"_a = std::map<std::string, std::pair<double, double>>{}, "solver"_a = default_solver,
      "model"_a = std::string("paper"), "threads"_a = py::int_(0),
      ("`skin fit --hex/--srgb`: the parameters (melanin, melanin_blend, hemoglobin by default) "
       "whose colour matches an 8-bit sRGB colour: hex='a98f74', srgb='169,143,116' or srgb=(169, 143, 116). "
       "melanin_blend_prior, melanin_blend_weight [Lab units]: the weak prior that resolves "
       "beta_m (paper model only). " + kModelDoc + " Returns target, parameters, fitted, delta_e_2000 (lists for one colour). "
       "N colours: srgb an array of shape (N, 3) (or hex a sequence of N texts), fitted on all "
       "cores (threads: worker threads, 0 = all) with the GIL released, each result bit for bit "
       "the one of fit_color(srgb=srgb[i], ...); returned as one dict shaped like a single result "
       "whose values are numpy arrays with a leading axis of length N (result['axes'] names it "
       "'target'; target.lab is (N, 3), parameters.melanin (N,), fitted.hex an array of str); "
       "melanin_blend_prior, melanin_blend_weight, model and free stay single; an uncertainty a single "
       "result gives as None is NaN. " + solver_doc() + params).c_str());

  m.def(
      "fit_texture",
      [color_fit_options](const py::object& image, const std::string& preset,
                          const std::optional<std::vector<std::string>>& free, double melanin_blend_prior,
                          double melanin_blend_weight,
                          const std::map<std::string, std::pair<double, double>>& bounds,
                          const std::string& solver, const std::string& model, bool uncertainty,
                          const py::kwargs& kw) {
        const fit::ColorFitOptions opt = color_fit_options(parameter_sets(preset, kw), free, melanin_blend_prior,
                                                           melanin_blend_weight, bounds, solver, model);
        image::Image img;
        // A file name: a text or a path object (pathlib.Path).
        py::object name = image;
        if (py::isinstance(image, py::module_::import("os").attr("PathLike")))
          name = py::module_::import("os").attr("fspath")(image);
        if (py::isinstance<py::str>(name)) {
          img = image::read_image(py::cast<std::string>(name));
        } else {
          const std::string allowed = "image must be a file name or an array of numbers of shape (height, width, 3) "
                                      "(height, width >= 1) of linear sRGB in [0, 1], not ";
          py::array raw;
          try {
            raw = py::module_::import("numpy").attr("asarray")(image);
          } catch (const py::error_already_set&) {  // ragged nested lists
            throw InputError(allowed + one_line(py::cast<std::string>(py::repr(image))).substr(0, 80));
          }
          const char kind = raw.dtype().kind();
          if ((kind != 'i' && kind != 'u' && kind != 'f') || raw.ndim() != 3 || raw.shape(2) != 3 ||
              raw.shape(0) < 1 || raw.shape(1) < 1 || raw.shape(0) > INT_MAX || raw.shape(1) > INT_MAX)
            throw InputError(allowed +
                             std::string(kind == 'O' || kind == 'U' || kind == 'S' || kind == 'b' || kind == 'c'
                                             ? "an array of " + py::cast<std::string>(py::str(raw.dtype())) + " of "
                                             : "") +
                             "shape " + py::cast<std::string>(py::str(raw.attr("shape"))));
          const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(raw);
          if (!a) throw py::error_already_set();
          img = image::Image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
          std::copy(a.data(), a.data() + a.size(), img.rgb.begin());
        }
        python::check_linear_rgb(img.rgb, static_cast<std::size_t>(img.width));
        const fit::ParameterMaps maps = interruptible([&] { return fit::TextureFitter(opt).fit(img, {}, uncertainty); });
        const Shape hw{maps.height, maps.width};
        auto plane = [&](const std::vector<float>& v) {
          return make_array<float>(hw, [&](float* o) { std::copy(v.begin(), v.end(), o); });
        };
        // The command's summary (without the files) and the maps themselves, float32 (y, x).
        py::dict d = to_python(schema::texture_fit_document(maps));
        d["melanin"] = plane(maps.melanin);
        d["melanin_blend"] = plane(maps.melanin_blend);
        d["hemoglobin"] = plane(maps.hemoglobin);
        d["error"] = plane(maps.error);
        py::dict axes;
        for (const char* k : {"melanin", "melanin_blend", "hemoglobin", "error"}) axes[k] = py::make_tuple("y", "x");
        for (std::size_t k = 0; k < maps.more_parameters.size(); ++k) {
          const std::string name(fit::key(maps.more_parameters[k]));
          d[py::str(name)] = plane(maps.more[k]);
          axes[py::str(name)] = py::make_tuple("y", "x");
        }
        for (std::size_t k = 0; k < maps.uncertainty_parameters.size(); ++k) {
          const std::string name = fit::uncertainty_channel(maps.uncertainty_parameters[k]);
          d[py::str(name)] = plane(maps.uncertainty[k]);
          axes[py::str(name)] = py::make_tuple("y", "x");
        }
        d["axes"] = axes;
        return d;
      },
      "image"_a, "preset"_a = std::string(kDefaultPreset), py::kw_only(), "free"_a = py::none(),
      "melanin_blend_prior"_a = 0.7, "melanin_blend_weight"_a = 0.2,
      "bounds"_a = std::map<std::string, std::pair<double, double>>{}, "solver"_a = default_solver,
      "model"_a = std::string("paper"), "uncertainty"_a = false,
      ("`skin fit --texture`: per-pixel parameter maps (float32, axes y, x) melanin, "
       "melanin_blend, hemoglobin and error (CIEDE2000) of an albedo texture: a file name (PNG, "
       "JPEG, ...; a text or a path object) or an array (height, width, 3) of linear sRGB in 0-1 "
       "(any numpy array of numbers, float32 or float64, any memory layout; copied as float32); on "
       "all cores with the GIL released. model='extended' adds a map per other free parameter "
       "(oxygenation, epidermis_thickness, dermis_scattering_scale, scattering_scale by default), named by its key. "
       "uncertainty=True adds one standard deviation per free parameter and texel, "
       "'uncertainty.<key>' (as fit_color()'s uncertainty). Options as fit_color(). " + solver_doc() + params).c_str());

  m.def(
      "export",
      [](const std::string& target, const std::string& preset, const std::string& solver,
         const std::optional<std::string>& units, double world_scale, const std::string& name,
         const py::object& gaussians, const py::object& taps, bool spectra_files, const py::object& progress,
         const py::kwargs& kw) {
        const Sets sets = parameter_sets(preset, kw);
        if (sets.size() != 1) throw InputError("export: one parameter set (no arrays)");
        exporting::Options o;
        if (units) o.unit = exporting::parse_unit(*units);
        o.world_scale = world_scale;
        o.name = name;
        o.gaussians = static_cast<int>(whole_number("gaussians", gaussians, INT_MIN, INT_MAX));
        o.taps = static_cast<int>(whole_number("taps", taps, INT_MIN, INT_MAX));
        o.spectra_files = spectra_files;
        const transport::Model& model = transport::find_model(solver);
        exporting::find_target(target);  // an unknown target before any solve
        PythonProgress reports(progress, exporting::prepare_wavelengths());
        announce_solves(static_cast<double>(exporting::prepare_solves(sets.values[0], model)),
                        exporting::prepare_wavelengths(), 0);
        const exporting::Export e = interruptible(
            [&] { return exporting::export_skin(target, sets.values[0], model, o, nullptr, reports.count()); },
            reports.poll());
        py::dict files;
        for (const auto& f : e.files) files[py::cast(f.suffix)] = f.content;
        py::dict images;
        for (const auto& im : e.images) {
          if (!im.planes.values.empty()) {
            const Shape hwc{im.planes.height, im.planes.width, static_cast<py::ssize_t>(im.planes.names.size())};
            images[py::cast(im.suffix)] = make_array<float>(hwc, [&](float* out) {
              const std::size_t n = im.planes.values[0].size(), k = im.planes.names.size();
              for (std::size_t i = 0; i < n; ++i)
                for (std::size_t c = 0; c < k; ++c) out[i * k + c] = im.planes.values[c][i];
            });
          } else {
            const Shape hwc{im.rgb.height, im.rgb.width, 3};
            images[py::cast(im.suffix)] = make_array<float>(
                hwc, [&](float* out) { std::copy(im.rgb.rgb.begin(), im.rgb.rgb.end(), out); });
          }
        }
        py::dict d;
        d["target"] = target;
        d["files"] = files;
        d["images"] = images;
        d["report"] = to_python(schema::fit_report_document(e.report, sets.values[0], solver, {}));
        return d;
      },
      "target"_a, "preset"_a = std::string(kDefaultPreset), py::kw_only(), "solver"_a = default_solver,
      "units"_a = py::none(), "world_scale"_a = 1.0, "name"_a = "spectral_skin", "gaussians"_a = py::int_(5),
      "taps"_a = py::int_(17), "spectra_files"_a = false, "progress"_a = py::none(),
      ("`skin export --target TARGET`: the files of a renderer or engine target (" +
       exporting::target_names_text() +
       ") as {suffix: text} ('' is the main file), images as float32 arrays (height, width, "
       "channels), and report: the fit's error as FILE.fit.json holds it (docs/export.md; its "
       "arrays of numbers as numpy arrays, its files empty). units: "
       "'mm', 'cm' or 'm' (default: the target's). " + std::string(kProgressDoc) + solver_doc() + params).c_str());
}
