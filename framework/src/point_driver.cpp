#include "stratum/point_driver.hpp"

#include "files.hpp"
#include "memory.hpp"
#include "scene/plugin_table.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "stratum/registry.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace stratum {

namespace {

using io::check_table;
using io::location;

// Axial = y (index 1), radial = x and z, as in an axisymmetric mesh.
constexpr int axial = voigt::yy;
// A row in memory (104 bytes), its CSV text (about 170 characters) and the text's copy when the
// file is written: 2e6 rows peaked at 0.92 GB (about 460 bytes per row); rounded up.
constexpr double bytes_per_row = 1000.0;

PointPath make_path(const std::string& type, const Params& p, const toml::table& t, const std::string& ctx) {
  PointPath path;
  path.name = type;
  path.steps = static_cast<int>(p.integer("steps"));
  auto stress = [&](std::initializer_list<int> comps) {
    for (int c : comps) path.stress_controlled[static_cast<std::size_t>(c)] = true;
  };
  if (type == "triaxial_drained") {
    // Radial stresses and shear stresses constant, axial strain prescribed.
    stress({0, 2, 3, 4, 5});
    path.increment[axial] = p.real("axial_strain");
  } else if (type == "triaxial_undrained") {
    // Isochoric: radial strains -1/2 of the axial strain; shears strain-free.
    const double e = p.real("axial_strain");
    path.increment << -e / 2, e, -e / 2, 0, 0, 0;
  } else if (type == "oedometer") {
    path.increment[axial] = p.real("axial_strain");
  } else if (type == "isotropic") {
    const bool has_p = t.get("pressure") != nullptr, has_e = t.get("volumetric_strain") != nullptr;
    if (has_p == has_e)
      throw Error(location(t),
                  ctx + " type = \"isotropic\" needs exactly one of pressure or volumetric_strain");
    if (has_p) {
      stress({0, 1, 2, 3, 4, 5});
      const double dp = p.real("pressure"); // compression positive change of p
      path.increment << -dp, -dp, -dp, 0, 0, 0;
    } else {
      const double ev = p.real("volumetric_strain");
      path.increment << ev / 3, ev / 3, ev / 3, 0, 0, 0;
    }
  } else if (type == "simple_shear") {
    // gamma_xy prescribed, sigma_yy constant, eps_xx = eps_zz = 0, other shears strain-free.
    stress({axial});
    path.increment[voigt::xy] = p.real("shear_strain");
  } else if (type == "mixed") {
    const auto& control = t.get("control");
    const auto* arr = control ? control->as_array() : nullptr;
    if (!arr || arr->size() != 6)
      throw Error(control ? location(*control) : location(t),
                  ctx + " control must be an array of 6 strings, each \"strain\" or \"stress\"");
    for (std::size_t i = 0; i < 6; ++i) {
      const auto* s = arr->get(i)->as_string();
      if (!s || (s->get() != "strain" && s->get() != "stress"))
        throw Error(location(*arr->get(i)), ctx + " control entries must be \"strain\" or \"stress\"");
      path.stress_controlled[i] = s->get() == "stress";
    }
    const auto& inc = p.real_list("increment");
    if (inc.size() != 6) throw Error(p.where("increment"), ctx + " increment must have 6 numbers");
    for (int i = 0; i < 6; ++i) path.increment[i] = inc[static_cast<std::size_t>(i)];
  }
  return path;
}

Schema path_schema(const std::string& type) {
  Schema s;
  s.text("type", {}, "path kind");
  s.integer("steps", "-", "increments of the segment").at_least(1).defaults_to(100LL);
  if (type == "triaxial_drained" || type == "triaxial_undrained" || type == "oedometer")
    s.real("axial_strain", "-", "total axial strain of the segment, tension positive (compression < 0)");
  if (type == "isotropic") {
    s.real("pressure", "kPa", "change of the compression-positive mean stress p").defaults_to(0.0);
    s.real("volumetric_strain", "-", "total volumetric strain, tension positive").defaults_to(0.0);
  }
  if (type == "simple_shear") s.real("shear_strain", "-", "engineering shear strain gamma_xy of the segment");
  if (type == "mixed") {
    s.real_list("increment", "- or kPa",
                "six increments: strain for strain-controlled, stress for stress-controlled");
  }
  return s;
}

/// `[material] from = "<name>"`: the material is the set [materials.<name>] of an included shared
/// file (inputs/materials/), the keys written in [material] beside `from` overriding the set's. The
/// set's values are moved in, keeping their source positions (messages point into the shared file).
void take_shared_set(toml::table& root, toml::table& mt) {
  toml::node* sets = root.get("materials");
  const toml::node* from = mt.get("from");
  if (!from) {
    if (sets)
      throw Error(location(*sets), "[materials] in a point file is used through [material] from = \"<name>\" "
                                   "(e.g. from = \"loess\" for [materials.loess] of an included file)");
    return;
  }
  if (!from->is_string())
    throw Error(location(*from),
                "[material] from = " + io::show(*from) +
                    "; allowed: the name of a [materials.<name>] table, e.g. from = \"loess\"");
  const std::string name = from->as_string()->get();
  toml::table* set = sets && sets->is_table() ? sets->as_table()->get_as<toml::table>(name) : nullptr;
  if (!set) {
    std::vector<std::string> known;
    if (sets && sets->is_table())
      for (auto&& [key, value] : *sets->as_table()) known.push_back(std::string(key.str()));
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw Error(location(*from), "[material] from = \"" + name + "\": no table [materials." + name +
                                     "] (include the shared file that holds it); known: " +
                                     (list.empty() ? "none" : list) + did_you_mean(name, known));
  }
  for (auto&& [set_key, value] : *set) {
    const toml::key key = set_key; // with its source position
    if (!mt.contains(key.str())) value.visit([&](auto&& v) { mt.insert(key, std::move(v)); });
  }
  mt.erase("from");
  root.erase("materials");
}

const std::vector<std::string> path_types{"triaxial_drained", "triaxial_undrained", "oedometer",
                                          "isotropic",        "simple_shear",       "mixed"};

} // namespace

struct PointDriver::Impl {
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::unique_ptr<Material> material;
  Vec6 initial = Vec6::Zero();
  std::vector<PointPath> paths;
  Units units;
};

PointDriver::PointDriver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
PointDriver::~PointDriver() = default;
const std::vector<PointPath>& PointDriver::paths() const { return impl_->paths; }

std::unique_ptr<PointDriver> PointDriver::from_file(const std::string& path, std::vector<std::string> dirs) {
  return from_string(read_text_file(path, SourceLocation{path, 0, 0}, "point file", file_limits::point), path,
                     std::move(dirs));
}

std::unique_ptr<PointDriver> PointDriver::from_string(const std::string& text, const std::string& path,
                                                      std::vector<std::string> dirs) {
  toml::table root = io::parse_with_includes(text, path);
  for (auto&& [key, value] : root)
    if (key.str() != "title" && key.str() != "units" && key.str() != "material" && key.str() != "initial" &&
        key.str() != "paths" && key.str() != "materials")
      throw Error(
          location(key.source()),
          "unknown key '" + std::string(key.str()) +
              "' at the top level; allowed: title, units, material, initial, paths, materials (an "
              "included shared set, taken by [material] from)" +
              did_you_mean(key.str(), {"title", "units", "material", "initial", "paths", "materials"}));
  auto impl = std::make_unique<Impl>();
  impl->units = scene::read_units(root); // stresses in force/length^2, the labels follow
  impl->catalog = std::make_unique<PluginCatalog>(dirs.empty() ? PluginCatalog::default_directories() : dirs);

  auto* mt = root.get("material") ? root.get("material")->as_table() : nullptr;
  if (!mt) throw Error(location(root), "point file needs a [material] table with model = \"...\"");
  take_shared_set(root, *mt);
  const std::string model = io::require_string(*mt, "model", "[material]");
  impl->material = scene::plugin_from_table<Material>(
      *impl->catalog, impl->registry, model, location(*mt->get("model")),
      "[material] model = \"" + model + "\"", *mt, "[material]", {"model"}, impl->units);

  Schema init;
  init.real_list("stress", "kPa", "initial stress xx, yy, zz, xy, yz, zx (tension positive)")
      .defaults_to(std::vector<double>{0, 0, 0, 0, 0, 0});
  init.real("p", "kPa", "initial isotropic pressure, compression positive (instead of stress)")
      .defaults_to(0.0);
  const toml::table empty;
  const auto* it = root.get("initial") ? root.get("initial")->as_table() : &empty;
  if (!it) throw Error(location(*root.get("initial")), "[initial] must be a table");
  const auto ip = check_table(*it, init, "[initial]", {}, impl->units);
  if (it->get("stress") && it->get("p"))
    throw Error(location(*it), "[initial] give either stress or p, not both");
  const auto& s = ip.real_list("stress");
  if (s.size() != 6)
    throw Error(ip.where("stress"), "[initial] stress must have 6 numbers (xx, yy, zz, xy, yz, zx)");
  for (int i = 0; i < 6; ++i) impl->initial[i] = s[static_cast<std::size_t>(i)];
  if (it->get("p")) impl->initial << -ip.real("p"), -ip.real("p"), -ip.real("p"), 0, 0, 0;
  io::require_read(ip, init, "[initial]");

  const auto* pn = root.get("paths");
  const auto* pa = pn ? pn->as_array() : nullptr;
  if (!pa || pa->empty())
    throw Error(pn ? location(*pn) : location(root), "point file needs at least one [[paths]]");
  const toml::node* most = nullptr; // the `steps` of the longest path, for the memory message
  int most_steps = 0;
  for (std::size_t i = 0; i < pa->size(); ++i) {
    const auto* t = pa->get(i)->as_table();
    const std::string ctx = "[[paths]] #" + std::to_string(i + 1);
    if (!t) throw Error(location(*pa->get(i)), ctx + " must be a table");
    const std::string type = io::require_string(*t, "type", ctx);
    if (std::find(path_types.begin(), path_types.end(), type) == path_types.end()) {
      std::string allowed;
      for (const auto& k : path_types) allowed += (allowed.empty() ? "" : ", ") + k;
      throw Error(location(*t->get("type")),
                  ctx + " type = \"" + type + "\" is not allowed; allowed: one of: " + allowed);
    }
    const auto p = check_table(*t, path_schema(type), ctx,
                               type == "mixed" ? std::vector<std::string_view>{"control"}
                                               : std::vector<std::string_view>{},
                               impl->units);
    impl->paths.push_back(make_path(p.text("type"), p, *t, ctx));
    io::require_read(p, path_schema(type), ctx);
    if (!most || impl->paths.back().steps > most_steps) {
      most_steps = impl->paths.back().steps;
      most = t->get("steps") ? t->get("steps") : t;
    }
  }
  // Every row stays in memory until the CSV is written (and the text is built in memory too):
  // refused up front rather than by std::bad_alloc or the kernel after minutes of work.
  double rows = 1.0;
  for (const auto& path : impl->paths) rows += static_cast<double>(path.steps);
  const double need = bytes_per_row * rows;
  char count[32], basis[64];
  std::snprintf(count, sizeof count, "%.0f", rows - 1.0);
  std::snprintf(basis, sizeof basis, "about %.0f bytes per row of the CSV", bytes_per_row);
  if (const auto no = memory_shortfall(need, std::string("the paths' ") + count + " steps", basis);
      !no.empty())
    throw Error(location(*most), no + ": use fewer steps");
  return std::unique_ptr<PointDriver>(new PointDriver(std::move(impl)));
}

PointRun PointDriver::run() const {
  const Material& m = *impl_->material;
  PointRun out;
  out.units = impl_->units;
  Vec6 stress = impl_->initial, strain = Vec6::Zero();
  std::vector<double> hist(static_cast<std::size_t>(m.history_size())), trial(hist.size());
  m.init_history(stress, hist);
  out.rows.push_back({0, 0, strain, stress});
  int step = 0;
  Mat6 tangent = Mat6::Zero();
  for (std::size_t seg = 0; seg < impl_->paths.size(); ++seg) {
    const PointPath& path = impl_->paths[seg];
    std::vector<int> S, E;
    for (int i = 0; i < 6; ++i) (path.stress_controlled[static_cast<std::size_t>(i)] ? S : E).push_back(i);
    const Vec6 stress0 = stress;
    Vec6 de_guess = Vec6::Zero();
    for (int j = 1; j <= path.steps; ++j) {
      Vec6 de = de_guess;
      for (int i : E) de[i] = path.increment[i] / path.steps;
      Vec6 target = stress0 + path.increment * (static_cast<double>(j) / path.steps);
      Vec6 s_new;
      Outcome o;
      bool converged = false;
      double rn = 0;
      // One stage whose increments are the steps of all paths, each of pseudo-time 1
      // (docs/design.md, "Time of a stage"): a material sees total time 0 on the first step only.
      PointContext where{
          0, 0, StepClock{static_cast<double>(step), static_cast<double>(step), 1.0, 1, step + 1}, {}, 0.0};
      for (int it = 0; it < 50; ++it) {
        MaterialOutput mo{s_new, trial, tangent};
        o = m.update(MaterialInput{stress, strain, hist, de, where}, mo);
        if (!o.ok()) break;
        if (S.empty()) {
          converged = true;
          break;
        }
        Eigen::VectorXd r(static_cast<Eigen::Index>(S.size()));
        Eigen::MatrixXd J(r.size(), r.size());
        for (std::size_t a = 0; a < S.size(); ++a) {
          r[static_cast<Eigen::Index>(a)] = s_new[S[a]] - target[S[a]];
          for (std::size_t b = 0; b < S.size(); ++b)
            J(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = tangent(S[a], S[b]);
        }
        rn = r.norm();
        if (!std::isfinite(rn)) {
          o = Outcome::failure(Status::non_finite, "stress is NaN or Inf");
          break;
        }
        if (rn <= 1e-10 * std::max(1.0, s_new.norm())) {
          converged = true;
          break;
        }
        Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
        if (!lu.isInvertible()) {
          o = Outcome::failure(Status::singular,
                               "the tangent of the stress-controlled components is singular "
                               "(perfect plasticity under stress control?)");
          break;
        }
        const Eigen::VectorXd d = lu.solve(r);
        for (std::size_t a = 0; a < S.size(); ++a) de[S[a]] -= d[static_cast<Eigen::Index>(a)];
      }
      // A start without stiffness answers every strain with no stress: the run would write rows
      // of the initial stress and exit 0 (found on 997ba04: a Duncan-Chang point from p = 0).
      // Only while the stress has never moved: a perfectly plastic state reached on the way (the
      // Drucker-Prager apex) legitimately has a zero tangent.
      if (o.ok() && converged && de.cwiseAbs().maxCoeff() > 0.0 && s_new == stress &&
          stress == impl_->initial && tangent.isZero(0.0))
        o = Outcome::failure(
            Status::singular,
            "the material has no stiffness at its initial state: the strain increment changed "
            "no stress component and its tangent is zero (e.g. Duncan-Chang at sigma_3 = 0, "
            "where E_i = K p_a (sigma_3/p_a)^n vanishes: start from [initial] p > 0)");
      if (o.ok() && !converged)
        o = Outcome::failure(Status::not_converged,
                             "mixed control did not converge in 50 iterations (|r| = " + std::to_string(rn) +
                                 " " + impl_->units.stress() + ")");
      if (!o.ok()) {
        out.outcome = Outcome::failure(o.status, "path " + std::to_string(seg + 1) + " (" + path.name +
                                                     "), step " + std::to_string(j) + ": " + o.message);
        return out;
      }
      de_guess = de; // next step starts from this step's strain increment
      stress = s_new;
      strain += de;
      hist = trial;
      out.rows.push_back({++step, static_cast<int>(seg + 1), strain, stress});
    }
  }
  return out;
}

void PointDriver::write_csv(const PointRun& run, const std::string& path) {
  std::ostringstream o;
  {
    o << "step,path,eps_xx,eps_yy,eps_zz,gamma_xy,gamma_yz,gamma_zx,sig_xx,sig_yy,sig_zz,sig_xy,sig_yz,sig_"
         "zx,"
         "eps_axial,eps_vol,"
      << run.units.column("p", "kPa") << ',' << run.units.column("q", "kPa") << '\n';
    o.precision(12);
    for (const auto& r : run.rows) {
      o << r.step << ',' << r.segment;
      for (int i = 0; i < 6; ++i) o << ',' << r.strain[i];
      for (int i = 0; i < 6; ++i) o << ',' << r.stress[i];
      const double p = -(r.stress[0] + r.stress[1] + r.stress[2]) / 3;
      const Vec6& s = r.stress;
      const double q = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                        (s[2] - s[0]) * (s[2] - s[0])) +
                                 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
      o << ',' << (0.0 - r.strain[axial]) << ',' << (0.0 - (r.strain[0] + r.strain[1] + r.strain[2])) << ','
        << p + 0.0 << ',' << q << '\n';
    }
  }
  write_file_atomically(path, o.str());
}

} // namespace stratum
