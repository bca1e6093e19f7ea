// The toolkit for declaring a plugin's parameters once (header only).
//
// A plugin spells each parameter name once: the declaration names it, gives its unit, meaning,
// range and default (the schema that `stratum check` and `stratum plugins --describe` use) and
// binds it to the member of the plugin's constants struct that receives it. Checks that need
// more than one parameter are declared beside them and name the parameter to blame, so every
// error is located at that key:
//
//   struct Constants { double E = 0, nu = 0.3, c = 0, phi = 0, psi = 0; Form form{}; };
//   stratum::Declared<Constants> d;
//   d.real(&Constants::E, "E", "kPa", "Young's modulus").greater_than(0.0);
//   d.choice(&Constants::form, "form", {{"exact", Form::exact}, {"rounded", Form::rounded}},
//            "shape of the surface").defaults_to(std::string("exact"));
//   d.check([](const Constants& c) -> std::optional<stratum::Problem> { ... });
//   registry.add(stratum::material_factory("my_model", "one line", d,
//       [](const Constants& c, const stratum::Params&) { return std::make_unique<MyModel>(c); }));
//
// docs/plugin-guide.md (section 4 and "The toolkit for model authors") explains it in full.
// TOML -> schema check (ranges, types, defaults; the scene reader) -> read() (binding, then the
// checks in the order declared) -> the constants the model computes with.
#pragma once

#include "stratum/error.hpp"
#include "stratum/params.hpp"
#include "stratum/registry.hpp"

#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace stratum {

/// What makes a parameter set inadmissible beyond the declared ranges: the parameter to blame
/// (its key locates the error) and why.
struct Problem {
  std::string parameter;
  std::string message;
};

/// A number for messages (six significant digits).
[[nodiscard]] inline std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// "[materials.soil] " (the block's context and a space) or "": the prefix of a plugin's messages.
[[nodiscard]] inline std::string message_prefix(const Params& p) {
  return p.context.empty() ? std::string() : p.context + " ";
}

/// Throws the located Error of a problem: at the key of its parameter, with the block's context.
[[noreturn]] inline void fail(const Params& p, const Problem& problem) {
  throw Error(p.where(problem.parameter), message_prefix(p) + problem.message);
}

/// The member of a member: nested(&Input::initial, &Initial::ocr) binds input.initial.ocr.
template <class Outer, class Inner, class M> struct Nested {
  Inner Outer::*outer;
  M Inner::*inner;
  M& operator()(Outer& o) const { return (o.*outer).*inner; }
  const M& operator()(const Outer& o) const { return (o.*outer).*inner; }
};
template <class Outer, class Inner, class M>
[[nodiscard]] Nested<Outer, Inner, M> nested(Inner Outer::*outer, M Inner::*inner) {
  return {outer, inner};
}

/// The parameters of one plugin, each declared once and bound to where its value goes in T
/// (a pointer to a member of T, or nested(); any callable T& -> member& binds, and one that also
/// takes a const T& can be used in declare_strength).
template <class T> class Declared {
public:
  /// The type of the member an accessor reaches.
  template <class At> using Member = std::remove_cvref_t<std::invoke_result_t<At, T&>>;
  using Check = std::function<std::optional<Problem>(const T&, const Params&)>;

  /// A real number.
  template <class At> ParamSpec& real(At at, std::string name, std::string unit, std::string meaning) {
    bind(at, name, [](const Params& p, const std::string& n) { return p.real(n); });
    return schema_.real(std::move(name), std::move(unit), std::move(meaning));
  }
  /// A whole number (the member may be any integer type).
  template <class At> ParamSpec& integer(At at, std::string name, std::string unit, std::string meaning) {
    bind(at, name, [](const Params& p, const std::string& n) { return p.integer(n); });
    return schema_.integer(std::move(name), std::move(unit), std::move(meaning));
  }
  /// A true/false switch.
  template <class At> ParamSpec& flag(At at, std::string name, std::string meaning) {
    bind(at, name, [](const Params& p, const std::string& n) { return p.flag(n); });
    return schema_.boolean(std::move(name), std::move(meaning));
  }
  /// A list of real numbers.
  template <class At> ParamSpec& real_list(At at, std::string name, std::string unit, std::string meaning) {
    bind(at, name, [](const Params& p, const std::string& n) { return p.real_list(n); });
    return schema_.real_list(std::move(name), std::move(unit), std::move(meaning));
  }
  /// One of a few words, each standing for a value of the member (usually an enum).
  template <class At>
  ParamSpec& choice(At at, std::string name, std::vector<std::pair<std::string, Member<At>>> options,
                    std::string meaning) {
    std::vector<std::string> words;
    for (const auto& o : options) words.push_back(o.first);
    binders_.push_back([at, name, options](T& t, const Params& p) {
      const std::string& w = p.text(name);
      for (const auto& [word, value] : options)
        if (word == w) std::invoke(at, t) = value;
    });
    return schema_.text(std::move(name), std::move(words), std::move(meaning));
  }

  /// A check of what the declared ranges cannot say (runs after binding, in declaration order).
  void check(Check c) { checks_.push_back(std::move(c)); }
  void check(std::function<std::optional<Problem>(const T&)> c) {
    checks_.push_back([c = std::move(c)](const T& t, const Params&) { return c(t); });
  }

  /// The schema, for the factory; also where parameters that bind to nothing are declared
  /// (framework groups such as plasticity::add_integrator_parameters, check-only values).
  [[nodiscard]] Schema& schema() { return schema_; }
  [[nodiscard]] const Schema& schema() const { return schema_; }

  /// The constants from validated parameters: `start` with every declared member set, then the
  /// checks; the first failing check throws its located Error.
  [[nodiscard]] T read(const Params& p, T start = T{}) const {
    for (const auto& b : binders_) b(start, p);
    for (const auto& c : checks_)
      if (const auto problem = c(start, p)) fail(p, *problem);
    return start;
  }

private:
  template <class At, class Get> void bind(At at, const std::string& name, Get get) {
    binders_.push_back([at, name, get](T& t, const Params& p) {
      auto& member = std::invoke(at, t);
      member = static_cast<std::remove_reference_t<decltype(member)>>(get(p, name));
    });
  }

  Schema schema_;
  std::vector<std::function<void(T&, const Params&)>> binders_;
  std::vector<Check> checks_;
};

/// A material factory from a declaration: its schema, and create = make(read(params), params),
/// reading from `start` (for members the parameters do not set).
template <class T, class Make>
[[nodiscard]] Factory<Material> material_factory(std::string name, std::string summary, Declared<T> d,
                                                 Make make, T start = T{}) {
  Factory<Material> f;
  f.name = std::move(name);
  f.summary = std::move(summary);
  f.schema = d.schema();
  f.create = [d = std::move(d), make, start](const Params& p) -> std::unique_ptr<Material> {
    return make(d.read(p, start), p);
  };
  return f;
}

/// Declares E and nu (as add_isotropic_elastic_parameters) bound to two members.
template <class T, class AtE, class AtNu>
void declare_isotropic_elastic(Declared<T>& d, AtE E, AtNu nu, std::string E_meaning = "Young's modulus",
                               std::string nu_meaning = "Poisson's ratio", double nu_default = 0.3) {
  d.real(E, "E", "kPa", std::move(E_meaning)).greater_than(0.0);
  d.real(nu, "nu", "-", std::move(nu_meaning)).greater_than(-1.0).less_than(0.5).defaults_to(nu_default);
}

/// How a plugin's Mohr-Coulomb strength parameters read (declare_strength).
struct StrengthText {
  std::string cohesion = "cohesion";
  std::string friction = "friction angle";
  std::string dilatancy =
      "dilatancy angle of the plastic potential, at most phi (psi = phi: associated flow)";
  std::optional<double> cohesion_default; ///< none: c is required
  bool frictionless = false;              ///< phi = 0 allowed, and the default (interfaces)
  bool zero_friction = false;             ///< phi = 0 allowed, no default (Tresca as a limit case)
};

/// Declares the strength parameters c (kPa, >= 0), phi (deg, (0, 90); [0, 90) default 0 when
/// frictionless) and psi (deg, [0, 90), default 0), bound to three members (in degrees), and the
/// check psi <= phi (located at psi).
template <class T, class AtC, class AtPhi, class AtPsi>
void declare_strength(Declared<T>& d, AtC c, AtPhi phi, AtPsi psi, const StrengthText& text = {}) {
  auto& cs = d.real(c, "c", "kPa", text.cohesion).at_least(0.0);
  if (text.cohesion_default) cs.defaults_to(*text.cohesion_default);
  auto& fs = d.real(phi, "phi", "deg", text.friction).less_than(90.0);
  if (text.frictionless)
    fs.at_least(0.0).defaults_to(0.0);
  else if (text.zero_friction)
    fs.at_least(0.0);
  else
    fs.greater_than(0.0);
  d.real(psi, "psi", "deg", text.dilatancy).at_least(0.0).less_than(90.0).defaults_to(0.0);
  d.check([phi, psi](const T& t, const Params&) -> std::optional<Problem> {
    const double f = std::invoke(phi, t), s = std::invoke(psi, t);
    if (s > f)
      return Problem{"psi", "the dilatancy angle psi = " + number(s) +
                                " must not exceed the friction angle phi = " + number(f)};
    return std::nullopt;
  });
}

/// One named history variable of a material: its name and unit ("-" when dimensionless).
struct HistoryVariable {
  const char* name;
  const char* unit;
};

/// Material::history_names() from a list of history variables: "name [unit]" each, in history
/// order, which is how they are named in the VTK output (ParaView shows the unit with the name).
template <std::size_t N>
[[nodiscard]] std::vector<std::string> history_names(const HistoryVariable (&vars)[N]) {
  std::vector<std::string> names;
  names.reserve(N);
  for (const auto& v : vars) names.push_back(std::string(v.name) + " [" + v.unit + "]");
  return names;
}

} // namespace stratum
