// The "umat" material: calls a user's Abaqus UMAT subroutine from a shared library.
// Header-only so the tests can reach the pieces; umat.cpp holds the factory and its schema.
// Call conventions and limits: README.md in this folder; component layout: umat_layout.hpp.
#pragma once

#include "umat_layout.hpp"

#include "stratum/error.hpp"
#include "stratum/material.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace stratum::umat {

/// The standard UMAT interface: every argument by reference (Fortran), CMNAME a CHARACTER*80
/// whose hidden length follows the last argument (gfortran passes it as size_t).
using UmatFunction = void (*)(double* stress, double* statev, double* ddsdde, double* sse, double* spd,
                              double* scd, double* rpl, double* ddsddt, double* drplde, double* drpldt,
                              double* stran, double* dstran, double* time, double* dtime, double* temp,
                              double* dtemp, double* predef, double* dpred, char* cmname, int* ndi, int* nshr,
                              int* ntens, int* nstatv, double* props, int* nprops, double* coords,
                              double* drot, double* pnewdt, double* celent, double* dfgrd0, double* dfgrd1,
                              int* noel, int* npt, int* layer, int* kspt, int* kstep, int* kinc,
                              std::size_t cmname_length);

/// An opened library and its UMAT entry point; closed when the last material using it goes.
class Library {
public:
  /// Opens `path` and looks up `symbol`; throws Error(message) without location on failure.
  Library(const std::string& path, const std::string& symbol) : path_(path) {
    dlerror();
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) throw Error("cannot load the UMAT library: " + one_line(dlerror()));
    dlerror();
    void* f = dlsym(handle_, symbol.c_str());
    if (!f) {
      const std::string why = one_line(dlerror());
      dlclose(handle_);
      throw Error("the UMAT library '" + path + "' has no symbol '" + symbol +
                  "' (gfortran names a SUBROUTINE UMAT 'umat_', a C function keeps its name; set symbol = "
                  "\"...\")" +
                  (why.empty() ? "" : ": " + why));
    }
    fn_ = reinterpret_cast<UmatFunction>(f);
  }
  ~Library() {
    if (handle_) dlclose(handle_);
  }
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;

  [[nodiscard]] UmatFunction function() const { return fn_; }
  [[nodiscard]] const std::string& path() const { return path_; }

private:
  static std::string one_line(const char* s) {
    std::string out = s ? s : "";
    for (char& c : out)
      if (c == '\n' || c == '\r') c = ' ';
    return out;
  }
  std::string path_;
  void* handle_ = nullptr;
  UmatFunction fn_ = nullptr;
};

/// What the scene fixes for every call.
struct Settings {
  std::string name;                      ///< material name (CMNAME, upper case, blank padded)
  std::vector<double> props;             ///< PROPS
  std::vector<std::string> prop_names;   ///< names of PROPS (messages), empty or one per entry
  int nstatv = 0;                        ///< NSTATV
  std::vector<double> statev;            ///< initial STATEV (NSTATV values)
  std::vector<std::string> statev_names; ///< output names of STATEV (NSTATV values)
  int ntens = 0;                         ///< 0: 4 when the out-of-plane shears are zero, else 6; or 4, 6
  double celent = 1.0;                   ///< CELENT
  double dtime = 1.0;                    ///< DTIME
  bool symmetric = false;                ///< the tangent is symmetric (Cholesky) or not (LU)
  bool thread_safe = false;              ///< false: one call at a time (a mutex)
};

/// The UMAT as a Stratum material. History per point: the NSTATV state variables, then SSE,
/// SPD, SCD (kept so the energies accumulate as in Abaqus).
class UmatMaterial final : public Material {
public:
  UmatMaterial(std::shared_ptr<const Library> lib, Settings s) : lib_(std::move(lib)), s_(std::move(s)) {
    cmname_.fill(' ');
    for (std::size_t i = 0; i < s_.name.size() && i < cmname_.size(); ++i)
      cmname_[i] = static_cast<char>(std::toupper(static_cast<unsigned char>(s_.name[i])));
  }

  [[nodiscard]] int history_size() const override { return s_.nstatv + 3; }
  void init_history(const Vec6& /*stress*/, std::span<double> h) const override {
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = i < s_.statev.size() ? s_.statev[i] : 0.0;
  }
  [[nodiscard]] std::vector<std::string> history_names() const override { return s_.statev_names; }
  [[nodiscard]] bool symmetric_tangent() const override { return s_.symmetric; }
  [[nodiscard]] const Settings& settings() const { return s_; }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    Outcome o = call(in, out);
    if (!o.ok()) { // leave the committed state in the outputs: nothing of a failed call survives
      out.stress = in.stress_n;
      for (std::size_t i = 0; i < out.history.size(); ++i)
        out.history[i] = i < in.history_n.size() ? in.history_n[i] : 0.0;
    }
    return o;
  }

private:
  [[nodiscard]] Outcome call(const MaterialInput& in, MaterialOutput& out) const {
    const bool plane = s_.ntens == 4 || (s_.ntens == 0 && in_plane(in.stress_n, in.strain_n, in.dstrain));
    const Layout l = plane ? Layout::plane() : Layout::three_d();
    if (s_.ntens == 4 && !in_plane(in.stress_n, in.strain_n, in.dstrain))
      return fail(in, Status::material_failure,
                  "ntens = 4 cannot carry the out-of-plane shears yz, zx of this state (use ntens = 6 or 0)");

    std::array<double, 6> stress{}, stran{}, dstran{};
    std::array<double, 36> ddsdde{};
    to_abaqus(l, in.stress_n, stress.data());
    to_abaqus(l, in.strain_n, stran.data());
    to_abaqus(l, in.dstrain, dstran.data());
    const std::size_t ns = static_cast<std::size_t>(s_.nstatv);
    std::vector<double> statev(std::max<std::size_t>(ns, 1), 0.0);
    for (std::size_t i = 0; i < ns && i < in.history_n.size(); ++i) statev[i] = in.history_n[i];
    double sse = 0, spd = 0, scd = 0;
    if (in.history_n.size() >= ns + 3)
      sse = in.history_n[ns], spd = in.history_n[ns + 1], scd = in.history_n[ns + 2];
    double rpl = 0, drpldt = 0, temp = 0, dtemp = 0, predef = 0, dpred = 0;
    std::array<double, 6> ddsddt{}, drplde{};
    std::array<double, 2> time{0.0, 0.0};
    double dtime = s_.dtime, celent = s_.celent, pnewdt = 1.0e36;
    std::array<double, 3> coords{};
    std::array<double, 9> drot{1, 0, 0, 0, 1, 0, 0, 0, 1}, dfgrd0 = drot, dfgrd1 = drot;
    int ndi = l.ndi, nshr = l.nshr, ntens = l.ntens, nstatv = s_.nstatv;
    int nprops = static_cast<int>(s_.props.size());
    std::vector<double> props = s_.props; // the UMAT may write to its arguments: give it a copy
    if (props.empty()) props.push_back(0.0);
    int noel = in.where.element + 1, npt = in.where.point + 1, layer = 1, kspt = 1, kstep = 1, kinc = 1;
    std::array<char, 80> cmname = cmname_;

    {
      std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
      if (!s_.thread_safe) lock.lock();
      lib_->function()(stress.data(), statev.data(), ddsdde.data(), &sse, &spd, &scd, &rpl, ddsddt.data(),
                       drplde.data(), &drpldt, stran.data(), dstran.data(), time.data(), &dtime, &temp,
                       &dtemp, &predef, &dpred, cmname.data(), &ndi, &nshr, &ntens, &nstatv, props.data(),
                       &nprops, coords.data(), drot.data(), &pnewdt, &celent, dfgrd0.data(), dfgrd1.data(),
                       &noel, &npt, &layer, &kspt, &kstep, &kinc, cmname.size());
    }

    if (pnewdt < 1.0)
      return fail(in, Status::material_failure,
                  "the UMAT asked for a smaller step (PNEWDT = " + number(pnewdt) + " < 1)");
    for (int i = 0; i < l.ntens; ++i)
      if (!std::isfinite(stress[static_cast<std::size_t>(i)]))
        return fail(in, Status::non_finite,
                    "the UMAT returned a non-finite STRESS(" + std::to_string(i + 1) + ")");
    for (std::size_t i = 0; i < ns; ++i)
      if (!std::isfinite(statev[i]))
        return fail(in, Status::non_finite,
                    "the UMAT returned a non-finite STATEV(" + std::to_string(i + 1) + ") (" +
                        s_.statev_names[i] + ")");
    if (in.want_tangent)
      for (int i = 0; i < l.ntens * l.ntens; ++i)
        if (!std::isfinite(ddsdde[static_cast<std::size_t>(i)]))
          return fail(in, Status::non_finite,
                      "the UMAT returned a non-finite DDSDDE(" + std::to_string(i % l.ntens + 1) + ", " +
                          std::to_string(i / l.ntens + 1) + ")");

    out.stress = from_abaqus(l, stress.data());
    for (std::size_t i = 0; i < out.history.size(); ++i)
      out.history[i] = i < ns ? statev[i] : i == ns ? sse : i == ns + 1 ? spd : i == ns + 2 ? scd : 0.0;
    if (in.want_tangent) out.tangent = tangent_from_abaqus(l, ddsdde.data());
    return Outcome::success();
  }

  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
  }

  [[nodiscard]] Outcome fail(const MaterialInput& in, Status st, const std::string& what) const {
    std::string m = "umat '" + s_.name + "' (element " + std::to_string(in.where.element) + ", point " +
                    std::to_string(in.where.point) + "; NOEL " + std::to_string(in.where.element + 1) +
                    ", NPT " + std::to_string(in.where.point + 1) + "): " + what;
    if (!s_.prop_names.empty()) {
      m += "; props";
      for (std::size_t i = 0; i < s_.props.size(); ++i)
        m += (i ? ", " : " ") + s_.prop_names[i] + " = " + number(s_.props[i]);
    }
    return Outcome::failure(st, m);
  }

  std::shared_ptr<const Library> lib_;
  Settings s_;
  std::array<char, 80> cmname_{};
  mutable std::mutex mutex_; ///< serializes the calls of a UMAT that is not thread-safe
};

} // namespace stratum::umat
