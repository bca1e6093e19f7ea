// The "umat" material: calls a user's Abaqus UMAT subroutine from a shared library.
// Header-only so the tests can reach the pieces; umat.cpp holds the factory and its schema.
// Call conventions and limits: README.md in this folder; component layout: umat_layout.hpp.
#pragma once

#include "abaqus_utilities.h"
#include "umat_layout.hpp"

#include "stratum/error.hpp"
#include "stratum/material.hpp"

#include <dlfcn.h>
#include <elf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <set>
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

/// The defined functions and objects of a shared library's dynamic symbol table (.dynsym) whose
/// names contain "umat" in any case, read from the ELF file itself (no program is run); empty
/// when the file is no 64-bit little-endian ELF file or has no such symbol.
[[nodiscard]] inline std::vector<std::string> umat_like_symbols(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string f((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::set<std::string> found;
  auto fits = [&](std::uint64_t off, std::uint64_t size) {
    return off <= f.size() && size <= f.size() - off;
  };
  Elf64_Ehdr eh;
  if (!fits(0, sizeof eh)) return {};
  std::memcpy(&eh, f.data(), sizeof eh);
  if (std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64 ||
      eh.e_ident[EI_DATA] != ELFDATA2LSB || eh.e_shentsize != sizeof(Elf64_Shdr))
    return {};
  auto section = [&](std::uint64_t i, Elf64_Shdr& sh) {
    if (i >= eh.e_shnum || !fits(eh.e_shoff + i * sizeof sh, sizeof sh)) return false;
    std::memcpy(&sh, f.data() + eh.e_shoff + i * sizeof sh, sizeof sh);
    return true;
  };
  for (std::uint64_t i = 0; i < eh.e_shnum; ++i) {
    Elf64_Shdr sym, str;
    if (!section(i, sym) || sym.sh_type != SHT_DYNSYM || !section(sym.sh_link, str)) continue;
    if (!fits(sym.sh_offset, sym.sh_size) || !fits(str.sh_offset, str.sh_size)) continue;
    for (std::uint64_t k = 0; k + sizeof(Elf64_Sym) <= sym.sh_size; k += sizeof(Elf64_Sym)) {
      Elf64_Sym e;
      std::memcpy(&e, f.data() + sym.sh_offset + k, sizeof e);
      const int type = ELF64_ST_TYPE(e.st_info);
      if (e.st_shndx == SHN_UNDEF || e.st_name >= str.sh_size || (type != STT_FUNC && type != STT_OBJECT))
        continue;
      const char* name = f.data() + str.sh_offset + e.st_name;
      const std::string n(name, strnlen(name, static_cast<std::size_t>(str.sh_size - e.st_name)));
      std::string lower = n;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (lower.find("umat") != std::string::npos) found.insert(n);
    }
  }
  return {found.begin(), found.end()};
}

/// Makes the utility routines (abaqus_utilities.h) visible to the libraries opened after this
/// call: the adapter plugin is opened RTLD_LOCAL, so its dependency libstratum_umat_utilities.so
/// is not in the global scope a UMAT's undefined XIT, SINV, ... resolve against until it is
/// opened again RTLD_GLOBAL (RTLD_NOLOAD: the loaded copy, never a second one).
inline void make_utilities_global() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&xit_), &info) == 0 || info.dli_fname == nullptr) return;
  if (void* h = dlopen(info.dli_fname, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD)) dlclose(h);
}

/// An opened library and its UMAT entry point; closed when the last material using it goes.
class Library {
public:
  /// Opens `path` and looks up `symbol`; throws Error(message) without location on failure.
  /// Opening resolves the library's undefined symbols (the utility routines included) and runs
  /// its constructors; no UMAT is called (`stratum check` stops here).
  Library(const std::string& path, const std::string& symbol) : path_(path) {
    make_utilities_global();
    dlerror();
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) throw Error("cannot load the UMAT library: " + one_line(dlerror()));
    dlerror();
    void* f = dlsym(handle_, symbol.c_str());
    if (!f) {
      dlerror();
      dlclose(handle_);
      const auto like = umat_like_symbols(path);
      std::string list;
      for (const auto& n : like) list += (list.empty() ? "" : ", ") + n;
      throw Error("the UMAT library '" + path + "' has no symbol '" + symbol + "'; " +
                  (like.empty() ? std::string("it exports no symbol whose name contains 'umat'")
                                : "it exports " + list) +
                  " (gfortran names a SUBROUTINE UMAT 'umat_', a module procedure '__<module>_MOD_umat', "
                  "a C function or bind(C, name=...) keeps its name; set symbol = \"...\")");
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
  double celent = 0.0;                   ///< CELENT; 0: the cell's characteristic length
  double stage_time = 1.0;               ///< the UMAT's time per unit of pseudo-time (one stage)
  bool symmetric = false;                ///< the tangent is symmetric (Cholesky) or not (LU)
  bool thread_safe = false;              ///< false: one call at a time (a mutex)
  std::string nstatv_at, props_at;       ///< "file:line:col" of nstatv and props in the scene, or ""
};

/// Guard values after the declared STATEV and PROPS (README.md, "Guards"): guard_size doubles
/// each, quiet NaNs with a payload of their own, so that a write past the end is seen after the
/// call and a value read past the end of PROPS is NaN and recognised where it arrives.
inline constexpr std::size_t guard_size = 64;
inline constexpr std::uint64_t statev_guard = 0x7FFA53544154455Full; // "STATE_"
inline constexpr std::uint64_t props_guard = 0x7FFB50524F505321ull;  // "PROPS!"

/// The UMAT as a Stratum material. History per point: the NSTATV state variables, then SSE,
/// SPD, SCD (kept so the energies accumulate as in Abaqus).
class UmatMaterial final : public Material {
  using Umat = UmatMaterial;

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
  /// The arguments of one UMAT call, for the trampoline stratum_umat_guarded_call runs (its
  /// frame may be left by XIT's longjmp: it holds only pointers).
  struct Call {
    UmatFunction fn;
    double *stress, *statev, *ddsdde, *sse, *spd, *scd, *rpl, *ddsddt, *drplde, *drpldt, *stran, *dstran,
        *time, *dtime, *temp, *dtemp, *predef, *dpred;
    char* cmname;
    int *ndi, *nshr, *ntens, *nstatv;
    double* props;
    int* nprops;
    double *coords, *drot, *pnewdt, *celent, *dfgrd0, *dfgrd1;
    int *noel, *npt, *layer, *kspt, *kstep, *kinc;
  };
  static void trampoline(void* p) {
    const Call& c = *static_cast<const Call*>(p);
    c.fn(c.stress, c.statev, c.ddsdde, c.sse, c.spd, c.scd, c.rpl, c.ddsddt, c.drplde, c.drpldt, c.stran,
         c.dstran, c.time, c.dtime, c.temp, c.dtemp, c.predef, c.dpred, c.cmname, c.ndi, c.nshr, c.ntens,
         c.nstatv, c.props, c.nprops, c.coords, c.drot, c.pnewdt, c.celent, c.dfgrd0, c.dfgrd1, c.noel, c.npt,
         c.layer, c.kspt, c.kstep, c.kinc, 80);
  }
  static std::uint64_t bits(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }
  static double from_bits(std::uint64_t b) {
    double v;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  /// A NaN that carries the PROPS guard's payload (whatever its sign): a value computed from a
  /// PROPS entry past NPROPS.
  static bool from_props_guard(double v) { return (bits(v) & 0x7FFFFFFFFFFFFFFFull) == props_guard; }

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
    // STATEV and PROPS with guard values after their declared lengths (README.md, "Guards").
    const std::size_t ns = static_cast<std::size_t>(s_.nstatv), np = s_.props.size();
    std::vector<double> statev(ns + guard_size, from_bits(statev_guard));
    for (std::size_t i = 0; i < ns; ++i) statev[i] = i < in.history_n.size() ? in.history_n[i] : 0.0;
    std::vector<double> props(np + guard_size, from_bits(props_guard)); // a copy: the UMAT may write
    std::copy(s_.props.begin(), s_.props.end(), props.begin());
    double sse = 0, spd = 0, scd = 0;
    if (in.history_n.size() >= ns + 3)
      sse = in.history_n[ns], spd = in.history_n[ns + 1], scd = in.history_n[ns + 2];
    double rpl = 0, drpldt = 0, temp = 0, dtemp = 0, predef = 0, dpred = 0;
    std::array<double, 6> ddsddt{}, drplde{};
    // Time (docs/design.md, "Time of a stage"): pseudo-time 1 per stage times stage_time; a call
    // without a clock (stage 0: a unit test) is the first increment of step 1 with DTIME 1.
    const StepClock& clock = in.where.clock;
    const bool timed = clock.stage > 0;
    std::array<double, 2> time{s_.stage_time * clock.step_time, s_.stage_time * clock.total_time};
    double dtime = timed ? s_.stage_time * clock.dtime : s_.stage_time;
    double celent = s_.celent > 0.0 ? s_.celent : in.where.length > 0.0 ? in.where.length : 1.0;
    double pnewdt = 1.0e36;
    std::array<double, 3> coords = in.where.x;
    // Small strains: no rotation, F = I + eps (the symmetric gradient) at the start and the end.
    std::array<double, 9> drot{1, 0, 0, 0, 1, 0, 0, 0, 1},
        dfgrd0 = small_strain_gradient(in.strain_n), dfgrd1 = small_strain_gradient(in.strain_n + in.dstrain);
    int ndi = l.ndi, nshr = l.nshr, ntens = l.ntens, nstatv = s_.nstatv;
    int nprops = static_cast<int>(np);
    int noel = in.where.element + 1, npt = in.where.point + 1, layer = 1, kspt = 1;
    int kstep = std::max(clock.stage, 1), kinc = std::max(clock.increment, 1);
    std::array<char, 80> cmname = cmname_;

    Call c{lib_->function(),
           stress.data(),
           statev.data(),
           ddsdde.data(),
           &sse,
           &spd,
           &scd,
           &rpl,
           ddsddt.data(),
           drplde.data(),
           &drpldt,
           stran.data(),
           dstran.data(),
           time.data(),
           &dtime,
           &temp,
           &dtemp,
           &predef,
           &dpred,
           cmname.data(),
           &ndi,
           &nshr,
           &ntens,
           &nstatv,
           props.data(),
           &nprops,
           coords.data(),
           drot.data(),
           &pnewdt,
           &celent,
           dfgrd0.data(),
           dfgrd1.data(),
           &noel,
           &npt,
           &layer,
           &kspt,
           &kstep,
           &kinc};
    int xit = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
      if (!s_.thread_safe) lock.lock();
      xit = stratum_umat_guarded_call(&Umat::trampoline, &c);
    }
    if (xit != 0)
      return fail(in, Status::fatal,
                  "the UMAT called XIT (the end of the analysis) in stage " + std::to_string(kstep) +
                      ", increment " + std::to_string(kinc));

    // The guards: a write past NSTATV or NPROPS ends the run (a configuration error).
    for (std::size_t i = ns + guard_size; i-- > ns;)
      if (bits(statev[i]) != statev_guard)
        return fail(in, Status::fatal,
                    "the UMAT wrote STATEV(" + std::to_string(i + 1) +
                        ") past NSTATV = " + std::to_string(ns) + at(s_.nstatv_at) +
                        "; set nstatv = " + std::to_string(i + 1) + " (or what the UMAT documents)");
    for (std::size_t i = np + guard_size; i-- > np;)
      if (bits(props[i]) != props_guard)
        return fail(in, Status::fatal,
                    "the UMAT wrote PROPS(" + std::to_string(i + 1) +
                        ") past NPROPS = " + std::to_string(np) + at(s_.props_at) + "; give props " +
                        std::to_string(i + 1) + " values (or what the UMAT documents)");

    if (pnewdt < 1.0)
      return fail(in, Status::material_failure,
                  "the UMAT asked for a smaller step (PNEWDT = " + number(pnewdt) + " < 1)");
    auto non_finite = [&](double v, const std::string& what) {
      if (from_props_guard(v))
        return fail(in, Status::fatal,
                    "the UMAT returned a non-finite " + what +
                        " computed from a PROPS entry past NPROPS = " + std::to_string(np) + at(s_.props_at) +
                        " (they hold NaN): it reads more PROPS than given; give them all");
      return fail(in, Status::non_finite,
                  "the UMAT returned a non-finite " + what +
                      " (the UMAT may read more PROPS than the NPROPS = " + std::to_string(np) + " given)");
    };
    for (int i = 0; i < l.ntens; ++i)
      if (!std::isfinite(stress[static_cast<std::size_t>(i)]))
        return non_finite(stress[static_cast<std::size_t>(i)], "STRESS(" + std::to_string(i + 1) + ")");
    for (std::size_t i = 0; i < ns; ++i)
      if (!std::isfinite(statev[i]))
        return non_finite(statev[i], "STATEV(" + std::to_string(i + 1) + ") (" + s_.statev_names[i] + ")");
    if (in.want_tangent)
      for (int i = 0; i < l.ntens * l.ntens; ++i)
        if (!std::isfinite(ddsdde[static_cast<std::size_t>(i)]))
          return non_finite(ddsdde[static_cast<std::size_t>(i)], "DDSDDE(" + std::to_string(i % l.ntens + 1) +
                                                                     ", " + std::to_string(i / l.ntens + 1) +
                                                                     ")");

    out.stress = from_abaqus(l, stress.data());
    for (std::size_t i = 0; i < out.history.size(); ++i)
      out.history[i] = i < ns ? statev[i] : i == ns ? sse : i == ns + 1 ? spd : i == ns + 2 ? scd : 0.0;
    if (in.want_tangent) out.tangent = tangent_from_abaqus(l, ddsdde.data());
    return Outcome::success();
  }

  /// DFGRD of small strains: I + eps (tensor strain, the Voigt vector's engineering shears
  /// halved), column-major 3 x 3 in Abaqus' axes 1, 2, 3 = x, y, z.
  static std::array<double, 9> small_strain_gradient(const Vec6& e) {
    std::array<double, 9> F{1 + e[voigt::xx],   0.5 * e[voigt::xy], 0.5 * e[voigt::zx],
                            0.5 * e[voigt::xy], 1 + e[voigt::yy],   0.5 * e[voigt::yz],
                            0.5 * e[voigt::zx], 0.5 * e[voigt::yz], 1 + e[voigt::zz]};
    return F;
  }

  /// " (scene.toml:12:1)" for a known place of a scene key, "" otherwise.
  static std::string at(const std::string& where) { return where.empty() ? where : " (" + where + ")"; }

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
