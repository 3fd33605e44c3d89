// The compiled module libbrdf._core (re-exported by the package libbrdf, python/libbrdf/__init__.py):
// numpy arrays in, numpy arrays out, through the batch API
// (libbrdf/batch.h), so that Python, `brdf eval` and the exporters give bit-identical values.
//
//   import libbrdf
//   m = libbrdf.Model("mbk", material="Au", sigma_s=0.05, lc=2, wavelength=0.55)
//   m(theta_i, theta_s, phi_s)       # degrees, any broadcastable shapes -> float64 array (1/sr)
//   m.directions(to_light, to_view)  # (..., 3) arrays in the surface frame (normal +z)
//   lut = libbrdf.bake("mbk", material="Au", sigma_s=0.05, lc=2); lut.error; lut.values
//   lut = libbrdf.Lut.open("gold.exr"); lut(30, 40, 180, channel=1)
//
// Errors: libbrdf.InvalidArgument (a ValueError with .parameter) for out-of-domain values,
// NaN included; TypeError for arrays of the wrong dtype or shape; libbrdf.LutFileError (an
// OSError) for unreadable or foreign table files.
//
// Model parameters go through libbrdf's option mapping (libbrdf/model_settings.h), the CLI's too,
// so that every keyword means exactly what the `brdf` option of the same name means.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "exporters/blender_export.h"
#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/materials.h"
#include "libbrdf/model_settings.h"
#include "libbrdf/models.h"
#include "libbrdf/version.h"

namespace py = pybind11;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Surface and material keywords shared by Model and bake (libbrdf::ModelSettings).
struct SurfaceKeywords {
  std::optional<double> sigma_s, lc, n, k, sigma_g, rho_s, rho_d;  // None: not given (an error where unread)
  std::optional<std::string> material, g_term;
  std::string k_mode = "plane";
  std::optional<std::string> sigma_g_mapping;
  double tolerance = 1e-6;

  libbrdf::ModelSettings settings(const std::string& name) const {
    libbrdf::ModelSettings s;
    s.model = name;
    s.sigma_s_um = sigma_s;
    s.lc_um = lc;
    s.n = n;
    s.kappa = k;
    s.sigma_g = sigma_g;
    s.rho_s = rho_s;
    s.rho_d = rho_d;
    s.material = material.value_or("");
    s.g_term = g_term;
    s.k_mode = k_mode;
    s.sigma_g_mapping = sigma_g_mapping;
    s.tolerance = tolerance;
    return s;
  }
};

// Python spells the CLI's hyphenated parameters with underscores (g-term -> g_term).
std::string python_name(std::string parameter) {
  for (char& c : parameter)
    if (c == '-') c = '_';
  return parameter;
}

// --- numpy input checks -------------------------------------------------------------------------

// Real numbers only (integers and floats; not bool, complex, strings or objects): anything else is
// a TypeError naming the argument.
py::array real_array(const py::handle& value, const char* name) {
  const py::object asarray = py::module_::import("numpy").attr("asarray");  // sys.modules lookup
  py::array a;
  try {
    a = asarray(value);
  } catch (py::error_already_set&) {  // ragged nested lists and the like
    throw py::type_error(std::string(name) + ": expected an array of real numbers");
  }
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected real numbers (float or integer), got dtype " +
                         py::str(a.dtype()).cast<std::string>());
  return a;
}

std::string shape_string(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Broadcasts the arguments against each other (numpy rules) and returns contiguous float64 copies
// (or views, when they already are).
std::vector<DoubleArray> broadcast(const std::vector<std::pair<py::handle, const char*>>& args) {
  const py::object broadcast_arrays = py::module_::import("numpy").attr("broadcast_arrays");
  py::list arrays;
  std::string names, shapes;
  for (const auto& [value, name] : args) {
    py::array a = real_array(value, name);
    names += (names.empty() ? "" : ", ") + std::string(name);
    shapes += (shapes.empty() ? "" : " ") + shape_string(a);
    arrays.append(a);
  }
  py::sequence broadcast_result;
  try {
    broadcast_result = broadcast_arrays(*arrays);
  } catch (py::error_already_set&) {
    throw py::type_error(names + ": shapes " + shapes + " do not broadcast together");
  }
  std::vector<DoubleArray> out;
  for (const auto& a : broadcast_result) out.push_back(DoubleArray::ensure(a));
  return out;
}

std::vector<py::ssize_t> shape_of(const py::array& a, py::ssize_t drop_last = 0) {
  return std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim() - drop_last);
}

// A float for 0-d results (as numpy's ufuncs give scalars for scalar input), else the array.
py::object result(DoubleArray values) {
  if (values.ndim() == 0) return py::float_(*values.data());
  return std::move(values);
}

std::vector<libbrdf::ScatterAngles> angles_from_degrees(const double* ti, const double* ts, const double* ps, std::size_t count) {
  // The CLI's conversion (scatter_angles_from_degrees), so that values are bit-identical.
  std::vector<libbrdf::ScatterAngles> angles(count);
  for (std::size_t k = 0; k < count; ++k) angles[k] = libbrdf::scatter_angles_from_degrees(ti[k], ts[k], ps[k]);
  return angles;
}

// f(angles, count, out) on the broadcast degree arrays, without the GIL. values_per_query > 0: out
// holds that many values per query, a trailing axis of the result (LutSampler's channels).
template <typename Batch>
py::object over_angles(py::handle theta_i, py::handle theta_s, py::handle phi_s, const Batch& batch, py::ssize_t values_per_query = 0) {
  const auto a = broadcast({{theta_i, "theta_i"}, {theta_s, "theta_s"}, {phi_s, "phi_s"}});
  std::vector<py::ssize_t> shape = shape_of(a[0]);
  if (values_per_query > 0) shape.push_back(values_per_query);
  DoubleArray out(shape);
  const std::size_t count = static_cast<std::size_t>(a[0].size());
  {
    py::gil_scoped_release release;
    const auto angles = angles_from_degrees(a[0].data(), a[1].data(), a[2].data(), count);
    batch(angles.data(), count, out.mutable_data());
  }
  return result(std::move(out));
}

// A function of theta_i only (degrees), element-wise over any array. Validates like the batch API.
template <typename F>
py::object over_theta_i(py::handle theta_i, const F& f) {
  const DoubleArray a = broadcast({{theta_i, "theta_i"}})[0];
  DoubleArray out(shape_of(a));
  const double* in = a.data();
  double* values = out.mutable_data();
  const std::size_t count = static_cast<std::size_t>(a.size());
  for (std::size_t k = 0; k < count; ++k) {  // all validated before anything is computed
    const double t = libbrdf::degrees_to_radians(in[k]);
    if (!(std::isfinite(t) && t >= 0.0 && t <= 0.5 * libbrdf::kPi))
      throw libbrdf::InvalidArgument("theta_i", "must be in [0, 90] degrees (got " + py::str(py::float_(in[k])).cast<std::string>() +
                                                    ") at query " + std::to_string(k));
  }
  {
    py::gil_scoped_release release;
    for (std::size_t k = 0; k < count; ++k) values[k] = f(libbrdf::degrees_to_radians(in[k]));
  }
  return result(std::move(out));
}

// --- Model --------------------------------------------------------------------------------------

struct PyModel {
  std::string name;
  double wavelength;
  libbrdf::Model model;
  std::string material;  // the built-in material's name, or "" when given as n, k
};

PyModel make_model(const std::string& name, double wavelength, const SurfaceKeywords& kw) {
  const libbrdf::ModelSettings settings = kw.settings(name);
  return PyModel{name, wavelength, libbrdf::Model(libbrdf::model_from_name(name), libbrdf::model_parameters(settings, wavelength)),
                 kw.material.value_or("")};
}

// repr(Model): the constructor call that makes it again -- material (name, else n and k), roughness
// (sigma_s, lc, and the microfacet parameters when set), wavelength; Python's shortest float text.
std::string model_repr(const PyModel& m) {
  const libbrdf::ModelParameters& p = m.model.parameters();
  const auto number = [](double value) { return py::repr(py::float_(value)).cast<std::string>(); };
  std::string text = "libbrdf.Model(" + py::repr(py::str(m.name)).cast<std::string>();
  if (!m.material.empty()) text += ", material=" + py::repr(py::str(m.material)).cast<std::string>();
  else if (p.index) text += ", n=" + number(p.index->n) + ", k=" + number(p.index->kappa);
  if (p.sigma_s_um) text += ", sigma_s=" + number(*p.sigma_s_um);
  if (p.lc_um) text += ", lc=" + number(*p.lc_um);
  if (p.sigma_g) text += ", sigma_g=" + number(*p.sigma_g);
  if (p.rho_s) text += ", rho_s=" + number(*p.rho_s);
  if (p.rho_d != 0.0) text += ", rho_d=" + number(p.rho_d);
  return text + ", wavelength=" + number(m.wavelength) + ")";
}

// The keyword names in a pybind11 function's signature line ("f(self: T, name: str, *, sigma_s:
// Optional[float] = None, ...) -> R", the first line of its __doc__): the text before ':' of each
// top-level item, "self" and the "*" marker left out.
std::vector<std::string> signature_keywords(const py::handle& function) {
  const std::string doc = py::str(function.attr("__doc__"));
  const std::size_t open = doc.find('(');
  std::vector<std::string> names;
  int depth = 0;
  std::string item;
  const auto take = [&] {
    const std::size_t colon = item.find(':');
    std::string name = item.substr(item.find_first_not_of(' '), colon == std::string::npos ? std::string::npos : colon - item.find_first_not_of(' '));
    if (colon != std::string::npos && name != "self") names.push_back(name);
    item.clear();
  };
  for (std::size_t i = open + 1; open != std::string::npos && i < doc.size() && doc[i] != '\n'; ++i) {
    const char c = doc[i];
    if (depth == 0 && c == ')') break;
    if (c == '(' || c == '[' || c == '{') ++depth;
    if (c == ')' || c == ']' || c == '}') --depth;
    if (depth == 0 && c == ',') take();
    else item += c;
  }
  take();
  return names;
}

// pybind11 answers a mistyped keyword with every overload's signature over several lines and does
// not name the keyword. Replaces scope.attribute by a function that first checks the keywords: an
// unknown one is a one-line TypeError naming it, a close match and the accepted names.
void check_keywords_first(py::object scope, const char* attribute, const std::string& shown_name, bool is_method) {
  py::object original = scope.attr(attribute);
  const std::vector<std::string> accepted = signature_keywords(original);
  std::string listed;
  for (const std::string& name : accepted) listed += (listed.empty() ? "" : ", ") + name;
  auto checked = [original, accepted, listed, shown_name](py::args args, py::kwargs kwargs) {
    for (const auto& item : kwargs) {
      const std::string keyword = py::str(item.first);
      if (std::find(accepted.begin(), accepted.end(), keyword) != accepted.end()) continue;
      const py::list close = py::module_::import("difflib").attr("get_close_matches")(keyword, py::cast(accepted), 1);
      const std::string hint = close.empty() ? "" : " (did you mean '" + close[0].cast<std::string>() + "'?)";
      throw py::type_error(shown_name + "() got an unexpected keyword argument '" + keyword + "'" + hint + "; accepted: " + listed);
    }
    return original(*args, **kwargs);
  };
  const std::string doc = py::str(original.attr("__doc__"));
  if (is_method)
    scope.attr(attribute) = py::cpp_function(checked, py::name(attribute), py::is_method(scope), py::doc(doc.c_str()));
  else
    scope.attr(attribute) = py::cpp_function(checked, py::name(attribute), py::scope(scope), py::doc(doc.c_str()));
}


py::object evaluate_directions(const PyModel& m, py::handle to_light, py::handle to_view) {
  py::array l = real_array(to_light, "to_light"), v = real_array(to_view, "to_view");
  for (const auto& [a, name] : {std::pair{l, "to_light"}, std::pair{v, "to_view"}})
    if (a.ndim() == 0 || a.shape(a.ndim() - 1) != 3)
      throw py::type_error(std::string(name) + ": expected an array of shape (..., 3), got " + shape_string(a));
  const auto a = broadcast({{l, "to_light"}, {v, "to_view"}});
  DoubleArray out(shape_of(a[0], 1));
  const std::size_t count = static_cast<std::size_t>(out.size());
  {
    py::gil_scoped_release release;
    libbrdf::evaluate_directions_batch(m.model, a[0].data(), a[1].data(), count, out.mutable_data());
  }
  return result(std::move(out));
}

py::dict parameters_dict(const PyModel& m) {
  const libbrdf::ModelParameters& p = m.model.parameters();
  py::dict d;
  d["sigma_s"] = p.sigma_s_um ? py::cast(*p.sigma_s_um) : py::none();
  d["lc"] = p.lc_um ? py::cast(*p.lc_um) : py::none();
  d["wavelength"] = p.wavelength_um;
  d["n"] = p.index ? py::cast(p.index->n) : py::none();
  d["k"] = p.index ? py::cast(p.index->kappa) : py::none();
  d["sigma_g"] = m.model.sigma_g();
  d["rho_s"] = p.rho_s ? py::cast(*p.rho_s) : py::none();
  d["rho_d"] = p.rho_d;
  d["tolerance"] = p.tolerance;
  return d;
}

// --- Lut ----------------------------------------------------------------------------------------

py::object lut_lookup(const libbrdf::Lut& lut, py::handle theta_i, py::handle theta_s, py::handle phi_s, int channel) {
  // lookup_batch also rejects geometries off a slice table's slice (eq. 5), as `brdf eval --lut`.
  return over_angles(theta_i, theta_s, phi_s, [&](const libbrdf::ScatterAngles* angles, std::size_t count, double* out) {
    libbrdf::lookup_batch(lut, channel, angles, count, out);
  });
}

void require_channel(const libbrdf::Lut& lut, int channel) {
  if (channel < 0 || channel >= lut.channels())
    throw libbrdf::InvalidArgument("channel", "must be in [0, " + std::to_string(lut.channels() - 1) + "] (got " +
                                                  std::to_string(channel) + ")");
}

py::dict error_dict(const libbrdf::LutError& e) {
  py::dict d;
  d["max_relative"] = e.max_relative;
  d["rms_relative"] = e.rms_relative;
  d["max_relative_all"] = e.max_relative_all;
  d["floor"] = e.floor;
  d["samples"] = e.samples;
  d["theta_limit_deg"] = e.theta_limit_deg;
  return d;
}

libbrdf::Direction direction(const std::optional<std::array<double, 3>>& d, const char* name) {
  if (!d) throw libbrdf::InvalidArgument(name, "required by layout slice (world direction, 3 numbers)");
  const auto& v = *d;
  for (double c : v) libbrdf::require_finite(name, c);
  if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.0)) throw libbrdf::InvalidArgument(name, "must be a nonzero vector");
  return {v[0], v[1], v[2]};
}

// libbrdf.bake: the CLI's `brdf bake` without the file (Lut.save writes it).
// wavelength=: one wavelength (a number) or one per channel (a sequence), um.
std::vector<double> channel_wavelength_list(const py::object& wavelength) {
  try {
    return py::isinstance<py::sequence>(wavelength) || py::isinstance<py::array>(wavelength)
               ? wavelength.cast<std::vector<double>>()
               : std::vector<double>{wavelength.cast<double>()};
  } catch (const py::cast_error&) {
    throw py::type_error("wavelength: expected a number or a sequence of numbers (um)");
  }
}

// resolution=: node counts per axis, each in [2, 4096], for a table of `axes` axes (1 beyond them).
std::array<int, 3> node_counts(const std::vector<int>& resolution, std::size_t axes) {
  if (resolution.size() != axes)
    throw libbrdf::InvalidArgument("resolution", "expected " + std::to_string(axes) + " node counts");
  std::array<int, 3> nodes{1, 1, 1};
  for (std::size_t k = 0; k < axes; ++k) {
    if (resolution[k] < 2 || resolution[k] > 4096)
      throw libbrdf::InvalidArgument("resolution", "node counts per axis must be in [2, 4096] (got " +
                                                       std::to_string(resolution[k]) + ")");
    nodes[k] = resolution[k];
  }
  return nodes;
}

// libbrdf.export_blender: `brdf export blender` in this process, through the same export_material
// (exporters/blender_export.h); the Blender extension bakes so, with no `brdf` program.
std::vector<std::string> export_blender(const std::string& name, const std::string& output,
                                        const std::vector<double>& wavelengths, const std::string& mode,
                                        const std::optional<std::vector<int>>& resolution,
                                        const std::optional<double>& target_error, const std::string& material_name,
                                        const SurfaceKeywords& kw) {
  const libbrdf::ModelSettings settings = kw.settings(name);
  libbrdf::blender::MaterialExportRequest request;
  request.model = libbrdf::model_from_name(name);
  request.mode = mode;
  request.output = output;
  if (resolution) request.resolution = node_counts(*resolution, 3);
  request.target_error = target_error;
  request.name = material_name;
  request.channels = libbrdf::channel_parameters(settings, wavelengths);
  py::gil_scoped_release release;
  return libbrdf::blender::export_material(request).written;
}

libbrdf::Lut bake(const std::string& name, const std::vector<double>& wavelengths, const std::string& layout,
                  const std::optional<std::vector<int>>& resolution, const std::optional<double>& target_error,
                  const std::optional<std::array<double, 3>>& light, const std::optional<std::array<double, 3>>& view,
                  int error_samples, double error_floor, std::uint64_t seed, const SurfaceKeywords& kw) {
  const libbrdf::ModelSettings settings = kw.settings(name);
  libbrdf::BakeRequest request;
  request.model = libbrdf::model_from_name(name);
  request.layout = libbrdf::layout_from_name(layout);
  const bool slice = request.layout == libbrdf::LutLayout::slice;
  if (slice) {
    request.light = direction(light, "light");
    request.view = direction(view, "view");
  } else if (light || view) {
    throw libbrdf::InvalidArgument(light ? "light" : "view", "only used by layout slice");
  }
  if (resolution) request.resolution = node_counts(*resolution, slice ? 2 : 3);
  request.target_error = target_error;
  request.error_samples = error_samples;
  request.error_floor_fraction = error_floor;
  request.seed = seed;
  request.channels = libbrdf::channel_parameters(settings, wavelengths);

  // Ctrl-C: the progress callback (calling thread) looks for a pending KeyboardInterrupt.
  std::atomic<bool> cancel{false};
  bool interrupted = false;
  request.cancel = &cancel;
  request.progress = [&](double) {
    py::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) {
      interrupted = true;
      cancel.store(true);
    }
  };
  try {
    py::gil_scoped_release release;
    return libbrdf::bake(request);
  } catch (const libbrdf::BakeCancelled&) {
    if (interrupted) throw py::error_already_set();
    throw;
  }
}

py::array_t<float> lut_values(const libbrdf::Lut& lut, py::handle owner) {
  // A read-only view of the table: [channel][i0][i1][i2] (slice: i2 has one node).
  const std::vector<py::ssize_t> shape{lut.channels(), lut.shape[0], lut.shape[1], lut.shape[2]};
  py::array_t<float> view(shape, lut.values.data(), owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

const char* albedo_path_name(libbrdf::AlbedoPath path) {
  switch (path) {
    case libbrdf::AlbedoPath::none: return "none";
    case libbrdf::AlbedoPath::surface_lobe: return "surface lobe";
    case libbrdf::AlbedoPath::facet_lobe: return "facet lobe";
  }
  return "?";
}

// A model's registry row (model_registry.h) as a dict; options in Python's spelling.
py::dict model_info(const std::string& name) {
  const libbrdf::ModelTraits& row = libbrdf::model_traits(libbrdf::model_from_name(name));
  py::list options, inputs, factors;
  for (libbrdf::ModelOption o : {libbrdf::kRhoS, libbrdf::kRhoD, libbrdf::kSigmaG, libbrdf::kGTerm, libbrdf::kSigmaGMapping})
    if (row.reads(o)) options.append(python_name(std::string(libbrdf::option_name(o))));
  for (const auto& [input, text] : {std::pair{libbrdf::kSigmaS, "sigma_s"}, std::pair{libbrdf::kLc, "lc"}, std::pair{libbrdf::kIndex, "n"}})
    if (row.needs(input)) inputs.append(text);
  for (const auto& [factor, text] : {std::pair{libbrdf::kFactorK, "K"}, std::pair{libbrdf::kFactorQBar, "Qbar"},
                                     std::pair{libbrdf::kFactorFresnelD, "F(theta_d)"}, std::pair{libbrdf::kFactorAsf, "A"}})
    if (row.multiplies(factor)) factors.append(text);
  py::dict d;
  d["name"] = std::string(row.name);
  d["formula"] = std::string(row.formula);
  d["equation"] = std::string(row.equation);
  d["brdf"] = row.is_brdf();
  d["inputs"] = inputs;
  d["options"] = options;
  d["factors"] = factors;
  d["spike"] = row.spike;
  d["asf_based"] = row.asf_based;
  d["albedo"] = albedo_path_name(row.albedo);
  return d;
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// --- The module's parts -------------------------------------------------------------------------

// libbrdf.InvalidArgument and libbrdf.LutFileError, and the translation of libbrdf's exceptions.
void register_exceptions(py::module_& m) {
  // InvalidArgument -> libbrdf.InvalidArgument(ValueError) with .parameter (Python spelling), .index.
  // Handles, not objects: a static py::object would be released after the interpreter is gone
  // (the module attributes keep the types alive).
  static const py::handle invalid_argument =
      py::exception<libbrdf::InvalidArgument>(m, "InvalidArgument", PyExc_ValueError).release();
  static const py::handle lut_file_error = py::exception<libbrdf::LutFileError>(m, "LutFileError", PyExc_OSError).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const libbrdf::InvalidArgument& e) {
      const std::string parameter = python_name(e.parameter());
      const std::string message = parameter + std::string(e.what()).substr(e.parameter().size());
      py::object instance = invalid_argument(message);
      instance.attr("parameter") = parameter;
      // The bad query's flat index in the broadcast shape (None for parameters of the model).
      const auto* query = dynamic_cast<const libbrdf::InvalidQuery*>(&e);
      instance.attr("index") = query ? py::cast(query->index()) : py::none();
      PyErr_SetObject(invalid_argument.ptr(), instance.ptr());
    } catch (const libbrdf::LutFileError& e) {
      PyErr_SetString(lut_file_error.ptr(), e.what());
    }
  });
}

// model_names, model_info, materials: what there is to choose from.
void define_catalogue(py::module_& m) {
  m.def("model_names", [] {
    std::vector<std::string> names;
    for (auto kind : libbrdf::all_models()) names.emplace_back(libbrdf::model_name(kind));
    return names;
  }, "Every quantity `Model` (and `brdf eval --model`) accepts, in the CLI's order.");
  m.def("model_info", &model_info, py::arg("name"),
        "A model's row of libbrdf's registry: formula, equation, brdf, inputs it requires, options it reads, "
        "factors, spike, asf_based, albedo path.");
  m.def("materials", [] {
    py::dict d;
    for (const auto& info : libbrdf::builtin_materials())
      d[py::str(info.name)] = py::dict(py::arg("description") = info.description, py::arg("source") = info.source,
                                       py::arg("wavelength_range_um") = py::make_tuple(info.min_wavelength_um, info.max_wavelength_um));
    return d;
  }, "Built-in materials (name -> description, source, tabulated wavelength range in um).");
}

void define_model_class(py::module_& m) {
  py::class_<PyModel>(m, "Model", R"doc(
A model (a named quantity of `brdf eval --model`) of one surface at one wavelength.

Model(name, *, sigma_s=None, lc=None, wavelength=0.55, n=None, k=None, material=None,
      sigma_g=None, rho_s=None, rho_d=None, g_term=None, k_mode="plane",
      sigma_g_mapping=None, tolerance=1e-6)

Every keyword means what the `brdf` option of the same name means (--sigma-s, --lc, ...):
lengths in micrometres, n + i k the complex index (or material="Au", ... at the wavelength).
None means the option's default (rho_d 0, g_term "smith", sigma_g_mapping "auto"); rho_s, rho_d
given to a model other than microfacet, or sigma_g, g_term, sigma_g_mapping to one other than
microfacet and mbk-fg, raise InvalidArgument: the model would not read them.
Out-of-domain values raise libbrdf.InvalidArgument (a ValueError) naming the parameter.
)doc")
      .def(py::init([](const std::string& name, std::optional<double> sigma_s, std::optional<double> lc, double wavelength,
                       std::optional<double> n, std::optional<double> k, std::optional<std::string> material,
                       std::optional<double> sigma_g, std::optional<double> rho_s, std::optional<double> rho_d,
                       std::optional<std::string> g_term, std::string k_mode, std::optional<std::string> sigma_g_mapping,
                       double tolerance) {
             SurfaceKeywords kw{sigma_s, lc, n, k, sigma_g, rho_s, rho_d, material, g_term, k_mode, sigma_g_mapping, tolerance};
             return make_model(name, wavelength, kw);
           }),
           py::arg("name"), py::kw_only(), py::arg("sigma_s") = py::none(), py::arg("lc") = py::none(),
           py::arg("wavelength") = 0.55, py::arg("n") = py::none(), py::arg("k") = py::none(),
           py::arg("material") = py::none(), py::arg("sigma_g") = py::none(), py::arg("rho_s") = py::none(),
           py::arg("rho_d") = py::none(), py::arg("g_term") = py::none(), py::arg("k_mode") = "plane",
           py::arg("sigma_g_mapping") = py::none(), py::arg("tolerance") = 1e-6)
      .def("__call__", [](const PyModel& self, py::handle theta_i, py::handle theta_s, py::handle phi_s) {
             const auto a = broadcast({{theta_i, "theta_i"}, {theta_s, "theta_s"}, {phi_s, "phi_s"}});
             DoubleArray out(shape_of(a[0]));
             {
               py::gil_scoped_release release;
               libbrdf::evaluate_degrees_batch(self.model, a[0].data(), a[1].data(), a[2].data(),
                                               static_cast<std::size_t>(a[0].size()), out.mutable_data());
             }
             return result(std::move(out));
           }, py::arg("theta_i"), py::arg("theta_s"), py::arg("phi_s"),
           "Values at angles in degrees (theta from the normal, phi_i = 0, in-plane forward scatter phi_s = 180), "
           "broadcast like numpy; the same values as `brdf eval`. Polar angles must be in [0, 90).")
      .def("directions", &evaluate_directions, py::arg("to_light"), py::arg("to_view"),
           "Values for direction arrays of shape (..., 3) in the surface frame (normal +z), both pointing away from "
           "the surface, any nonzero length; broadcast against each other.")
      .def("specular_reflectance", [](const PyModel& self, py::handle theta_i) {
             return over_theta_i(theta_i, [&](double t) { return self.model.specular_reflectance(t); });
           }, py::arg("theta_i"), "R_spec(theta_i) = F(ti) exp(-g(ti, ti)), the specular spike's reflectance (0 for models without one); degrees.")
      .def("renormalization", [](const PyModel& self, py::handle theta_i) {
             return over_theta_i(theta_i, [&](double t) { return self.model.renormalization(t); });
           }, py::arg("theta_i"), "K(theta_i) as this model uses it (1 where it has none); degrees.")
      .def_readonly("name", &PyModel::name)
      .def_readonly("wavelength", &PyModel::wavelength)
      .def_property_readonly("sigma_g", [](const PyModel& self) { return self.model.sigma_g(); },
                             "The microfacet slope parameter in use (given or mapped by eqs 20/25; 0 if none).")
      .def_property_readonly("parameters", &parameters_dict)
      .def("__repr__", &model_repr);
}

void define_lut_classes(py::module_& m) {
  py::class_<libbrdf::Lut>(m, "Lut", "A baked table (libbrdf.bake or Lut.open): lookups on arrays, its measured error, its values.")
      .def_static("open", [](const std::string& path) {
        py::gil_scoped_release release;
        return libbrdf::read_lut_file(path);
      }, py::arg("path"), "Reads an OpenEXR table or a MERL binary (chosen by content).")
      .def("__call__", &lut_lookup, py::arg("theta_i"), py::arg("theta_s"), py::arg("phi_s"), py::kw_only(), py::arg("channel") = 0,
           "Interpolated values of one channel at angles in degrees, as `brdf eval --lut`.")
      .def("specular_reflectance", [](const libbrdf::Lut& self, py::handle theta_i, int channel) {
             require_channel(self, channel);
             return over_theta_i(theta_i, [&](double t) { return self.specular_at(channel, t); });
           }, py::arg("theta_i"), py::kw_only(), py::arg("channel") = 0)
      .def("renormalization", [](const libbrdf::Lut& self, py::handle theta_i, int channel) {
             require_channel(self, channel);
             return over_theta_i(theta_i, [&](double t) { return self.renormalization_at(channel, t); });
           }, py::arg("theta_i"), py::kw_only(), py::arg("channel") = 0)
      .def("save", [](const libbrdf::Lut& self, const std::string& path) {
             py::gil_scoped_release release;
             if (ends_with(path, ".binary")) libbrdf::write_merl_binary(self, path);
             else if (ends_with(path, ".exr")) libbrdf::write_lut_exr(self, path);
             else throw libbrdf::InvalidArgument("path", "must end in .exr (OpenEXR) or .binary (MERL) (got '" + path + "')");
           }, py::arg("path"), "Writes the table (.exr, or .binary for the merl layout with 3 channels); no partial file on failure.")
      .def_property_readonly("layout", [](const libbrdf::Lut& self) { return std::string(libbrdf::layout_name(self.layout)); })
      .def_property_readonly("shape", [](const libbrdf::Lut& self) { return self.shape; })
      .def_property_readonly("wavelengths", [](const libbrdf::Lut& self) { return self.wavelengths_um; })
      .def_property_readonly("channels", &libbrdf::Lut::channels)
      .def_property_readonly("error", [](const libbrdf::Lut& self) { return error_dict(self.error); },
                             "Measured at bake time against the model at random off-grid points (lut.h, LutError).")
      .def_property_readonly("attributes", [](const libbrdf::Lut& self) { return self.attributes; })
      .def_property_readonly("values", [](py::object self) { return lut_values(self.cast<const libbrdf::Lut&>(), self); },
                             "The table, read-only float32 [channel][i0][i1][i2] (1/sr).")
      .def("__repr__", [](const libbrdf::Lut& self) {
        return "libbrdf.Lut(" + std::string(libbrdf::layout_name(self.layout)) + " " + libbrdf::shape_text(self.shape, self.layout) +
               ", " + std::to_string(self.channels()) + " channel(s))";
      });

  py::class_<libbrdf::LutSampler>(m, "LutSampler",
                                  "A table prepared for lookups of all its channels at once (lut.h): sampler(theta_i, "
                                  "theta_s, phi_s) gives Lut(...) of every channel, bit for bit, as an array [..., channel]; "
                                  "faster for RGB (channel-interleaved nodes for rusinkiewicz, merl and the kernel layout's P~ table). Keeps its own copy.")
      .def(py::init<libbrdf::Lut>(), py::arg("lut"))
      .def("__call__", [](const libbrdf::LutSampler& self, py::handle theta_i, py::handle theta_s, py::handle phi_s) {
             return over_angles(
                 theta_i, theta_s, phi_s,
                 [&](const libbrdf::ScatterAngles* angles, std::size_t count, double* out) { libbrdf::lookup_all_batch(self, angles, count, out); },
                 self.lut().channels());
           }, py::arg("theta_i"), py::arg("theta_s"), py::arg("phi_s"))
      .def_property_readonly("lut", &libbrdf::LutSampler::lut, py::return_value_policy::reference_internal)
      .def("__repr__", [](const libbrdf::LutSampler& self) {
        return "libbrdf.LutSampler(" + std::string(libbrdf::layout_name(self.lut().layout)) + " " +
               libbrdf::shape_text(self.lut().shape, self.lut().layout) + ", " + std::to_string(self.lut().channels()) + " channel(s))";
      });
}

void define_bake(py::module_& m) {
  m.def("bake",
        [](const std::string& name, py::object wavelength, const std::string& layout, std::optional<std::vector<int>> resolution,
           std::optional<double> target_error, std::optional<std::array<double, 3>> light, std::optional<std::array<double, 3>> view,
           int error_samples, double error_floor, std::uint64_t seed, std::optional<double> sigma_s, std::optional<double> lc,
           std::optional<double> n, std::optional<double> k, std::optional<std::string> material, std::optional<double> sigma_g,
           std::optional<double> rho_s, std::optional<double> rho_d, std::optional<std::string> g_term, std::string k_mode,
           std::optional<std::string> sigma_g_mapping, double tolerance) {
          SurfaceKeywords kw{sigma_s, lc, n, k, sigma_g, rho_s, rho_d, material, g_term, k_mode, sigma_g_mapping, tolerance};
          return bake(name, channel_wavelength_list(wavelength), layout, resolution, target_error, light, view, error_samples,
                      error_floor, seed, kw);
        },
        py::arg("name"), py::kw_only(), py::arg("wavelength") = py::make_tuple(0.65, 0.55, 0.45),
        py::arg("layout") = "rusinkiewicz", py::arg("resolution") = py::none(), py::arg("target_error") = py::none(),
        py::arg("light") = py::none(), py::arg("view") = py::none(), py::arg("error_samples") = 20000,
        py::arg("error_floor") = 1e-3, py::arg("seed") = 1, py::arg("sigma_s") = py::none(), py::arg("lc") = py::none(),
        py::arg("n") = py::none(), py::arg("k") = py::none(), py::arg("material") = py::none(), py::arg("sigma_g") = py::none(),
        py::arg("rho_s") = py::none(), py::arg("rho_d") = py::none(), py::arg("g_term") = py::none(), py::arg("k_mode") = "plane",
        py::arg("sigma_g_mapping") = py::none(), py::arg("tolerance") = 1e-6,
        R"doc(
Bakes a BRDF into a table, as `brdf bake` (same keywords as Model; wavelength: one per channel,
default (0.65, 0.55, 0.45)). layout: rusinkiewicz | merl | slice (light=, view= world directions);
resolution: nodes per axis, or target_error: the smallest table whose measured max relative error
meets it. Returns a Lut; lut.error holds the measured error. Ctrl-C cancels.
)doc");
}

void define_export_blender(py::module_& m) {
  m.def("export_blender",
        [](const std::string& name, const std::string& output, py::object wavelength, const std::string& mode,
           std::optional<std::vector<int>> resolution, std::optional<double> target_error, const std::string& material_name,
           std::optional<double> sigma_s, std::optional<double> lc, std::optional<double> n, std::optional<double> k,
           std::optional<std::string> material, std::optional<double> sigma_g, std::optional<double> rho_s,
           std::optional<double> rho_d, std::optional<std::string> g_term, std::string k_mode,
           std::optional<std::string> sigma_g_mapping) {
          SurfaceKeywords kw{sigma_s, lc, n, k, sigma_g, rho_s, rho_d, material, g_term, k_mode, sigma_g_mapping, 1e-6};
          return export_blender(name, output, channel_wavelength_list(wavelength), mode, resolution, target_error,
                                material_name, kw);
        },
        py::arg("model"), py::arg("output"), py::kw_only(), py::arg("wavelength") = py::make_tuple(0.65, 0.55, 0.45),
        py::arg("mode") = "lut", py::arg("resolution") = py::none(), py::arg("target_error") = py::none(),
        py::arg("name") = "", py::arg("sigma_s") = py::none(), py::arg("lc") = py::none(), py::arg("n") = py::none(),
        py::arg("k") = py::none(), py::arg("material") = py::none(), py::arg("sigma_g") = py::none(),
        py::arg("rho_s") = py::none(), py::arg("rho_d") = py::none(), py::arg("g_term") = py::none(),
        py::arg("k_mode") = "plane", py::arg("sigma_g_mapping") = py::none(),
        R"doc(
A material for the Blender add-on, as `brdf export blender` writes it (the same files, bit for bit):
output DIR/NAME.json (DIR created), mode lut | osl | fit, wavelength one or three (R, G, B),
resolution (3 node counts) or target_error, the surface keywords of Model. Returns the paths written.
)doc");
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "libbrdf: MBK, Beckmann-Kirchhoff and microfacet BRDFs (Butler, Nauyoks & Marciniak 2015) on numpy arrays";
  m.attr("__version__") = libbrdf::kVersion;
  register_exceptions(m);
  define_catalogue(m);
  define_model_class(m);
  define_lut_classes(m);
  define_bake(m);
  define_export_blender(m);
  // One-line TypeErrors for mistyped keywords (check_keywords_first), after every definition.
  check_keywords_first(m.attr("Model"), "__init__", "Model", /*is_method=*/true);
  check_keywords_first(m, "bake", "bake", /*is_method=*/false);
  check_keywords_first(m, "export_blender", "export_blender", /*is_method=*/false);
}
