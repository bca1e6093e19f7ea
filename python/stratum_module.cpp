// `import stratum`: the compiled part (stratum._stratum), bound with pybind11 (docs/python.md).
// The package's Python part (python/stratum/__init__.py) re-exports these and adds the reader of
// a result folder.
//
//   run(path=None, text=None, overrides=None, out=None, write_output=True, progress=None)
//       a scene from a file or a TOML text, with values replaced by path ("materials.soil.E"),
//       run with the GIL released; `progress(step, steps, lambda)` after every accepted step.
//       Ctrl-C (KeyboardInterrupt) ends the run at its next step, writes what was computed (as
//       SIGINT does for `stratum run`) and is raised again.
//   check(path=None, text=None, overrides=None)  -> the reader's warnings
//   point(path=None, text=None, overrides=None)  -> the material-point driver's path
//   plugins()                                    -> {kind: [names]}
//   sweep(path, out=None, progress=None)         -> the samples of `stratum sweep` (one process)
//   calibrate(path, out=None, progress=None)     -> the result of `stratum calibrate` (one process)
//   Error: a located input error, with .file, .line, .column and .message.
#include "stratum/analysis.hpp"
#include "stratum/error.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/point_driver.hpp"
#include "stratum/registry.hpp"

#include "files.hpp"
#include "scene/toml_check.hpp"
#include "sweep/back_analysis.hpp"
#include "sweep/sweep.hpp"
#include "sweep/sweep_toml.hpp"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include <filesystem>
#include <optional>
#include <sstream>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

using stratum::Error;

/// A 2-D float64 array of `rows` rows of `cols` values.
template <class Rows> py::array_t<double> matrix(const Rows& rows, std::size_t cols) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(cols)});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < cols; ++j)
      m(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = j < rows[i].size() ? rows[i][j] : NAN;
  return a;
}

/// A Python value as a TOML node: bool, int, float, str, or a list of them.
void assign_value(toml::table& root, const std::string& path, const py::handle& v) {
  namespace d = stratum::sweep::detail;
  if (py::isinstance<py::bool_>(v)) {
    d::assign(root, path, toml::value<bool>(v.cast<bool>()));
  } else if (py::isinstance<py::int_>(v)) {
    d::assign(root, path, toml::value<int64_t>(v.cast<int64_t>()));
  } else if (py::isinstance<py::float_>(v)) {
    d::assign(root, path, toml::value<double>(v.cast<double>()));
  } else if (py::isinstance<py::str>(v)) {
    d::assign(root, path, toml::value<std::string>(v.cast<std::string>()));
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    toml::array a;
    for (const auto& e : v) {
      if (py::isinstance<py::bool_>(e))
        a.push_back(e.cast<bool>());
      else if (py::isinstance<py::int_>(e))
        a.push_back(e.cast<int64_t>());
      else if (py::isinstance<py::float_>(e))
        a.push_back(e.cast<double>());
      else if (py::isinstance<py::str>(e))
        a.push_back(e.cast<std::string>());
      else
        throw Error("override '" + path + "': a list may hold numbers, booleans and strings only");
    }
    d::assign(root, path, a);
  } else {
    throw Error("override '" + path +
                "': the value must be a number, a boolean, a string or a list of them, not " +
                std::string(py::str(py::type::of(v).attr("__name__"))));
  }
}

/// The scene's text and the path that names it: the file (or `text`) with the overrides set.
/// With overrides, a place in an error is a line of the overridden text (stratum.scene_text
/// shows it), as for a sweep's sample.
std::pair<std::string, std::string> scene_source(const std::optional<std::string>& path,
                                                 const std::optional<std::string>& text,
                                                 const py::dict& overrides) {
  if (path.has_value() == text.has_value())
    throw Error("give the scene as path=... or as text=..., one of them");
  const std::string where = path ? *path : "<text>";
  std::string body = path ? stratum::read_text_file(*path, stratum::SourceLocation{*path, 0, 0}, "scene file",
                                                    stratum::file_limits::scene)
                          : *text;
  if (overrides.empty()) return {body, where};
  toml::table root = stratum::io::parse_with_includes(body, where);
  for (const auto& [k, v] : overrides) {
    const std::string key = py::str(k);
    try {
      assign_value(root, key, v);
    } catch (const stratum::sweep::detail::PathError& e) {
      throw Error("override '" + key + "': " + e.message + " (in " + where + ")");
    }
  }
  std::ostringstream o;
  o << root << "\n";
  return {o.str(), where};
}

/// The TOML text of a scene with its overrides (what a located error of an overridden scene counts
/// lines in).
std::string scene_text(const std::optional<std::string>& path, const std::optional<std::string>& text,
                       const py::dict& overrides) {
  return scene_source(path, text, overrides).first;
}

const char* status_of(const stratum::RunSummary& s) {
  if (!s.outcome.ok()) return "failed";
  return s.stop_reason == stratum::StopReason::none ? "completed" : "stopped";
}

py::dict summary_dict(const stratum::RunSummary& s) {
  py::dict d;
  d["status"] = status_of(s);
  d["stop_reason"] = stratum::stop_reason_name(s.stop_reason);
  d["message"] = s.outcome.ok() ? s.stop_message : s.outcome.message;
  d["steps"] = s.steps_done;
  d["cutbacks"] = s.cutbacks;
  d["stages_done"] = s.stages_done;
  d["out_dir"] = s.out_dir;
  d["pvd"] = s.pvd;
  py::list checks;
  for (const auto& c : s.checks) {
    py::dict e;
    e["label"] = c.label;
    e["unit"] = c.unit;
    e["value"] = c.value;
    e["expected"] = c.expected;
    e["tolerance"] = c.tolerance;
    e["pass"] = c.pass;
    checks.append(e);
  }
  d["checks"] = checks;
  py::dict t;
  t["assembly"] = s.times.assembly;
  t["factorize"] = s.times.factorize;
  t["solve"] = s.times.solve;
  t["output"] = s.times.output;
  t["total"] = s.times.total;
  d["times"] = t;
  return d;
}

py::dict run(const std::optional<std::string>& path, const std::optional<std::string>& text,
             const py::dict& overrides, const std::optional<std::string>& out, bool write_output,
             const py::object& progress) {
  const auto [body, where] = scene_source(path, text, overrides);
  stratum::RunOptions o;
  o.write_output = write_output;
  if (out) o.out_dir = *out;
  // A Python exception raised in the callback or by Ctrl-C: kept, the run stopped at its next
  // step (its files written as for SIGINT), and raised again when the run has returned.
  std::optional<py::error_already_set> pending;
  o.on_step = [&](int step, int steps, double lambda, const stratum::StepReport&) {
    if (progress.is_none() || pending) return;
    py::gil_scoped_acquire gil;
    try {
      progress(step, steps, lambda);
    } catch (py::error_already_set& e) {
      pending.emplace(std::move(e));
    }
  };
  o.interrupted = [&] {
    if (pending) return true;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) pending.emplace(); // fetches the KeyboardInterrupt
    return pending.has_value();
  };
  std::unique_ptr<stratum::Analysis> a;
  stratum::RunSummary s;
  {
    py::gil_scoped_release release;
    a = path && overrides.empty() ? stratum::Analysis::from_file(*path, o)
                                  : stratum::Analysis::from_string(body, where, o);
    s = a->run();
  }
  if (pending) throw std::move(*pending);
  py::dict r;
  r["load_settlement"] = matrix(s.load_settlement, 2);
  r["settlement_components"] = matrix(s.settlement_components, 8);
  py::dict rec;
  for (const auto& t : a->recorded()) {
    py::dict cols;
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      py::array_t<double> v(static_cast<py::ssize_t>(t.rows.size()));
      auto m = v.mutable_unchecked<1>();
      for (std::size_t k = 0; k < t.rows.size(); ++k)
        m(static_cast<py::ssize_t>(k)) = c < t.rows[k].size() ? t.rows[k][c] : NAN;
      cols[py::str(t.columns[c])] = v;
    }
    rec[py::str(t.name)] = cols;
  }
  r["recorders"] = rec;
  r["summary"] = summary_dict(s);
  r["title"] = a->title();
  const auto& u = a->units();
  py::dict units;
  for (const char* q : {"kN", "m", "kPa", "mm", "s"}) units[q] = u.label(q);
  r["units"] = units;
  return r;
}

py::list check(const std::optional<std::string>& path, const std::optional<std::string>& text,
               const py::dict& overrides) {
  const auto [body, where] = scene_source(path, text, overrides);
  stratum::RunOptions o;
  o.write_output = false;
  std::unique_ptr<stratum::Analysis> a;
  {
    py::gil_scoped_release release;
    a = path && overrides.empty() ? stratum::Analysis::from_file(*path, o)
                                  : stratum::Analysis::from_string(body, where, o);
  }
  py::list w;
  for (const auto& line : a->warnings()) w.append(line);
  return w;
}

py::dict point(const std::optional<std::string>& path, const std::optional<std::string>& text,
               const py::dict& overrides) {
  const auto [body, where] = scene_source(path, text, overrides);
  std::unique_ptr<stratum::PointDriver> d;
  stratum::PointRun r;
  {
    py::gil_scoped_release release;
    d = path && overrides.empty() ? stratum::PointDriver::from_file(*path)
                                  : stratum::PointDriver::from_string(body, where);
    r = d->run();
  }
  std::vector<std::array<double, 6>> e, s;
  py::array_t<int> steps(static_cast<py::ssize_t>(r.rows.size()));
  auto st = steps.mutable_unchecked<1>();
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    std::array<double, 6> a{}, b{};
    for (int i = 0; i < 6; ++i)
      a[static_cast<std::size_t>(i)] = r.rows[k].strain[i],
      b[static_cast<std::size_t>(i)] = r.rows[k].stress[i];
    e.push_back(a);
    s.push_back(b);
    st(static_cast<py::ssize_t>(k)) = r.rows[k].step;
  }
  py::dict out;
  out["step"] = steps;
  out["strain"] = matrix(e, 6);
  out["stress"] = matrix(s, 6);
  out["components"] = std::vector<std::string>{"xx", "yy", "zz", "xy", "yz", "zx"};
  out["status"] = r.outcome.ok() ? "completed" : "failed";
  out["message"] = r.outcome.message;
  return out;
}

py::dict plugins() {
  const stratum::PluginCatalog catalog(stratum::PluginCatalog::default_directories());
  py::dict d;
  for (auto k : stratum::all_plugin_kinds) d[stratum::to_string(k)] = catalog.known(k);
  return d;
}

py::dict calibrate(const std::string& path, const std::optional<std::string>& out,
                   const py::object& progress) {
  namespace sw = stratum::sweep;
  const sw::BackAnalysis ba = sw::BackAnalysis::from_file(path);
  const std::string dir = out ? *out : (fs::path("out") / fs::path(path).stem()).string();
  fs::create_directories(dir);
  sw::Journal journal((fs::path(dir) / "journal.csv").string(), ba.hash(), ba.parameters().size(),
                      ba.points());
  const sw::BatchRunner local = [&ba](const std::vector<std::vector<double>>& batch) {
    std::vector<sw::Evaluation> ev;
    for (const auto& p : batch) ev.push_back(ba.evaluate(p));
    return ev;
  };
  sw::FitResult r;
  std::optional<py::error_already_set> pending; // an exception of the callback, raised at the end
  {
    py::gil_scoped_release release;
    r = sw::calibrate(ba, sw::journaled(journal, local), [&](int it, double cost, int runs) {
      if (progress.is_none() || pending) return;
      py::gil_scoped_acquire gil;
      try {
        progress(it, cost, runs);
      } catch (py::error_already_set& e) {
        pending.emplace(std::move(e));
      }
    });
  }
  if (pending) throw std::move(*pending);
  const auto files = sw::report_files(ba, r);
  for (const auto& [name, body] : files)
    stratum::write_file_atomically((fs::path(dir) / name).string(), body);
  py::dict d;
  py::dict params;
  for (std::size_t j = 0; j < ba.parameters().size(); ++j) {
    py::dict p;
    p["value"] = r.best[j];
    p["ci95"] = py::make_tuple(r.low95[j], r.high95[j]);
    p["determined"] = static_cast<bool>(r.determined[j]);
    p["at_bound"] = static_cast<bool>(r.at_bound[j]);
    params[py::str(ba.parameters()[j].target.name)] = p;
  }
  d["parameters"] = params;
  d["correlation"] =
      py::array_t<double>({r.correlation.rows(), r.correlation.cols()},
                          {sizeof(double), sizeof(double) * static_cast<std::size_t>(r.correlation.rows())},
                          r.correlation.data());
  d["singular_values"] = std::vector<double>(r.singular.data(), r.singular.data() + r.singular.size());
  d["sigma"] = r.sigma;
  d["dof"] = r.dof;
  d["iterations"] = r.iterations;
  d["runs"] = r.runs;
  d["converged"] = r.converged;
  d["notes"] = r.notes;
  d["report"] = files.at("report.md");
  d["out_dir"] = dir;
  return d;
}

/// `stratum sweep` on this process: every sample in order; returns the header, the rows (as
/// samples.csv has them) and writes samples.csv to `out` when given.
py::dict sweep(const std::string& path, const std::optional<std::string>& out, const py::object& progress) {
  namespace sw = stratum::sweep;
  const sw::Study study = sw::Study::from_file(path);
  const std::string dir = out ? *out : std::string();
  py::list rows, status;
  std::string csv = study.header() + "\n";
  std::optional<py::error_already_set> pending;
  const auto n = study.samples().size();
  for (std::size_t i = 0; i < n && !pending; ++i) {
    sw::SampleResult r;
    {
      py::gil_scoped_release release;
      r = study.run(static_cast<int>(i), dir);
    }
    csv += r.row + "\n";
    rows.append(r.row);
    status.append(r.status);
    if (PyErr_CheckSignals() != 0) pending.emplace(); // Ctrl-C between samples
    if (!pending && !progress.is_none()) {
      try {
        progress(static_cast<int>(i) + 1, static_cast<int>(n), r.status);
      } catch (py::error_already_set& e) {
        pending.emplace(std::move(e));
      }
    }
  }
  if (pending) throw std::move(*pending);
  if (out) stratum::write_file_atomically((fs::path(dir) / "samples.csv").string(), csv);
  py::dict d;
  d["header"] = study.header();
  d["rows"] = rows;
  d["status"] = status;
  d["csv"] = csv;
  return d;
}

} // namespace

PYBIND11_MODULE(_stratum, m) {
  m.doc() = "Stratum's compiled core (import stratum; docs/python.md)";
  py::object error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "stratum.Error", "A Stratum input error: .file, .line, .column (0 when unknown) and .message",
      PyExc_ValueError, nullptr));
  m.attr("Error") = error;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      py::object cls = py::module_::import("stratum._stratum").attr("Error");
      py::object inst = cls(e.what());
      inst.attr("file") = e.where().file;
      inst.attr("line") = e.where().line;
      inst.attr("column") = e.where().column;
      inst.attr("message") = e.message();
      PyErr_SetObject(cls.ptr(), inst.ptr());
    }
  });
  m.def("run", &run, py::arg("path") = py::none(), py::arg("text") = py::none(),
        py::arg("overrides") = py::dict(), py::arg("out") = py::none(), py::arg("write_output") = true,
        py::arg("progress") = py::none());
  m.def("check", &check, py::arg("path") = py::none(), py::arg("text") = py::none(),
        py::arg("overrides") = py::dict());
  m.def("scene_text", &scene_text, py::arg("path") = py::none(), py::arg("text") = py::none(),
        py::arg("overrides") = py::dict());
  m.def("point", &point, py::arg("path") = py::none(), py::arg("text") = py::none(),
        py::arg("overrides") = py::dict());
  m.def("plugins", &plugins);
  m.def("sweep", &sweep, py::arg("path"), py::arg("out") = py::none(), py::arg("progress") = py::none());
  m.def("calibrate", &calibrate, py::arg("path"), py::arg("out") = py::none(),
        py::arg("progress") = py::none());
}
