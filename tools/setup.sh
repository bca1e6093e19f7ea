# Shared set-up of tools/run, tools/test and tools/bench (sourced, not run).
# STRATUM_EXTRA_PACKAGES adds Debian packages to install (tools/bench: calculix-ccx, matplotlib).
# STRATUM_CMAKE_ARGS (a bash array set before sourcing) adds options to the first configure
# (tools/ci_sanitize: clang and the sanitizers).
# STRATUM_NO_BUILD=1 installs the packages only (tools/check_format, tools/check_tidy: they need no
# build; tools/check_tidy then calls stratum_configure for the compile_commands.json).
# Installs the Debian packages Stratum needs when they are missing, then
# configures and builds the Release tree in build/release.
set -euo pipefail

STRATUM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
STRATUM_BUILD="${STRATUM_BUILD:-$STRATUM_ROOT/build/release}"
STRATUM_PACKAGES=(cmake ninja-build g++ gfortran pkg-config libeigen3-dev libboost-dev libboost-filesystem-dev libboost-serialization-dev libvtk9-dev
  libsundials-dev libtomlplusplus-dev libceres-dev catch2 libsuitesparse-dev libopenblas0-pthread python3-matplotlib python3-vtk9
  python3-dev pybind11-dev python3-numpy python3-pytest # import stratum (docs/python.md)
  libopenmpi-dev openmpi-bin
  clang libclang-rt-14-dev llvm # tools/ci_sanitize: sanitizers, libFuzzer, llvm-symbolizer for the reports
  clang-format clang-tidy-22 git # tools/check_format, tools/check_tidy (docs/testing.md, "Style and tidy checks")
  ${STRATUM_EXTRA_PACKAGES:-})

stratum_install_packages() {
  local missing=()
  for p in "${STRATUM_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "tools: installing ${missing[*]}" >&2
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

stratum_configure() {
  # Configure once; afterwards the build re-runs CMake itself when a CMakeLists.txt changes, and
  # a tree configured otherwise (STRATUM_BUILD=build/debug, as the loess-pile CTest case passes
  # its own tree) keeps its build type.
  # A tree whose first configure failed (a cache but no build system) is configured again.
  # ccache when the machine has it (not installed by default): rebuilds after a header change, and
  # several worktrees of one repository, then share what did not change.
  local launcher=()
  command -v ccache >/dev/null &&
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  [[ -f "$STRATUM_BUILD/CMakeCache.txt" && (-f "$STRATUM_BUILD/build.ninja" || -f "$STRATUM_BUILD/Makefile") ]] ||
    cmake -S "$STRATUM_ROOT" -B "$STRATUM_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
      ${STRATUM_CMAKE_ARGS[@]+"${STRATUM_CMAKE_ARGS[@]}"} >/dev/null
}

stratum_build() {
  stratum_configure
  # getconf, not nproc: nproc honours the OMP_NUM_THREADS=1 exported below and built on one core.
  # STRATUM_BUILD_TARGET (tools/run: stratum_program) builds only that target; unset: everything.
  cmake --build "$STRATUM_BUILD" -j "$(getconf _NPROCESSORS_ONLN)" \
    ${STRATUM_BUILD_TARGET:+--target "$STRATUM_BUILD_TARGET"}
}

# One BLAS thread: on two shared cores two threads were slower (docs/performance.md).
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
# Likewise CHOLMOD's OpenMP threads: with them, factorizations on the loaded 2-core machines
# took about twice as long (tools/benchmarks/README.md, bench_ccx).
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"

stratum_install_packages
[[ "${STRATUM_NO_BUILD:-0}" == 1 ]] || stratum_build
