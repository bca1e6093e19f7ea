#!/usr/bin/env bash
# The plugin SDK test (CTest: sdk.out_of_tree_plugin).
#
#   run.sh <stratum build dir> <tests/sdk dir> <work dir>
#
# 1. installs the built framework into <work>/prefix (headers, libstratum, the
#    in-tree plugins, the CMake package config, the stratum program);
# 2. configures and builds tests/sdk/example_plugin against that prefix only
#    (find_package(Stratum) + stratum_add_plugin), into <work>/build;
# 3. checks that the installed stratum finds its own plugins and, through
#    STRATUM_PLUGIN_PATH, the example plugin (`stratum plugins --describe`);
# 4. checks that the schema's range reaches the user as a located error;
# 5. `stratum check` and `stratum run --out` a Lamé cylinder made of the example
#    material, and runs the example's own test program, which compares u(a)
#    with the closed form;
# 6. the same cylinder from the example's stage action and mesh generator plugins
#    (lame_kg_staged.toml): check, run, located schema errors, u(a) against the closed form.
# Exits non-zero with a message naming the failed check.
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 <stratum build dir> <tests/sdk dir> <work dir>" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
sdk=$(cd "$2" && pwd)
work=$3

fail() {
  echo "sdk test FAILED: $*" >&2
  exit 1
}
step() { echo "== $*"; }
# run_logged <log file> <command...>: runs quietly, shows the log on failure.
run_logged() {
  local log=$1
  shift
  if ! "$@" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    fail "'$*' failed (full log: $log)"
  fi
}

case "$work" in
  "" | "/" | "$HOME") fail "refusing to use '$work' as the work directory" ;;
esac
rm -rf -- "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
prefix=$work/prefix
example_src=$sdk/example_plugin
example_build=$work/build
scene=$example_src/lame_kg.toml

# --- 1. install ------------------------------------------------------------------
step "install $build -> $prefix"
[[ -f $build/CMakeCache.txt ]] || fail "$build is not a configured build tree"
run_logged "$work/install.log" cmake --install "$build" --prefix "$prefix"
for f in include/stratum/plugin.hpp include/stratum/material.hpp include/stratum/analysis.hpp \
  bin/stratum lib/cmake/Stratum/StratumConfig.cmake lib/cmake/Stratum/StratumConfigVersion.cmake \
  lib/cmake/Stratum/StratumTargets.cmake lib/cmake/Stratum/StratumPlugin.cmake; do
  [[ -e $prefix/$f ]] || fail "the install lacks $f"
done
libdir=$(dirname "$(find "$prefix" -name 'libstratum.so*' -print -quit)")
[[ -d $libdir ]] || fail "the install lacks libstratum.so"
for p in quad linear_elastic newton; do
  [[ -f $libdir/stratum/plugins/stratum_$p.so && -f $libdir/stratum/plugins/stratum_$p.plugin ]] ||
    fail "the install lacks plugin $p in $libdir/stratum/plugins"
done
echo "   headers, package config, bin/stratum, ${libdir#"$prefix"/}/libstratum.so and 3 plugins installed"
# The installed program must run on the installed library (its RUNPATH), not the build tree's.
if command -v ldd >/dev/null 2>&1; then
  resolved=$(ldd "$prefix/bin/stratum" | sed -n 's/.*libstratum\.so[^ ]* => \([^ ]*\).*/\1/p')
  [[ $(realpath "$resolved") == "$(realpath "$libdir")"/* ]] ||
    fail "the installed stratum resolves libstratum to '$resolved', not into $libdir"
  echo "   bin/stratum runs on $resolved"
fi

# --- 2. build the example against the installed package --------------------------
step "build $example_src against $prefix"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
compiler=()
[[ -n $cxx ]] && compiler=(-DCMAKE_CXX_COMPILER="$cxx")
run_logged "$work/configure.log" cmake "${generator[@]}" -S "$example_src" -B "$example_build" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" "${compiler[@]}"
grep -q "Stratum_DIR:PATH=$libdir/cmake/Stratum" "$example_build/CMakeCache.txt" ||
  fail "find_package(Stratum) did not pick the installed package ($(grep '^Stratum_DIR' "$example_build/CMakeCache.txt"))"
run_logged "$work/build.log" cmake --build "$example_build"
plugin_dir=$example_build/plugins
[[ -f $plugin_dir/example_kg_elastic.so ]] || fail "no $plugin_dir/example_kg_elastic.so"
grep -qx "material example_kg_elastic" "$plugin_dir/example_kg_elastic.plugin" ||
  fail "the manifest $plugin_dir/example_kg_elastic.plugin does not list 'material example_kg_elastic'"
echo "   built example_kg_elastic.so, its manifest and test_kg_elastic"

stratum=$prefix/bin/stratum
# Only the example's directory on the search path: everything else must come from the install.
export STRATUM_PLUGIN_PATH=$plugin_dir

# --- 3. the installed program finds both kinds of plugins -------------------------
step "stratum plugins --describe"
out=$("$stratum" plugins --describe linear_elastic) || fail "stratum plugins --describe linear_elastic failed"
grep -q "library: $prefix/.*stratum/plugins/stratum_linear_elastic.so" <<<"$out" ||
  fail "the installed stratum did not load its installed plugins:"$'\n'"$out"
echo "   linear_elastic comes from the install"
out=$("$stratum" plugins --describe example_kg_elastic) || fail "stratum plugins --describe example_kg_elastic failed"
sed 's/^/   | /' <<<"$out"
for pattern in "^material example_kg_elastic: " "library: $plugin_dir/example_kg_elastic.so" \
  "^  K  *number  *kPa  *(0, inf), required" "^  G  *number  *kPa  *(0, inf), required" "bulk modulus" "shear modulus"; do
  grep -q -- "$pattern" <<<"$out" || fail "'stratum plugins --describe example_kg_elastic' lacks /$pattern/"
done

# --- 4. schema errors reach the user with a location ------------------------------
step "a bad parameter is refused before anything runs"
sed 's/^G = 600.0 /G = -600.0/' "$scene" >"$work/bad_G.toml"
grep -q "^G = -600.0" "$work/bad_G.toml" || fail "could not make the bad scene"
if err=$("$stratum" check "$work/bad_G.toml" 2>&1); then
  fail "stratum check accepted G = -600"
fi
echo "   $err"
grep -q "bad_G.toml:[0-9]*:[0-9]*.*G" <<<"$err" || fail "the error does not name bad_G.toml:line:col and G"
if err=$(env -u STRATUM_PLUGIN_PATH "$stratum" check "$scene" 2>&1); then
  fail "stratum check found example_kg_elastic without STRATUM_PLUGIN_PATH"
fi
grep -q "example_kg_elastic" <<<"$err" || fail "the unknown-material error does not name example_kg_elastic: $err"
echo "   without STRATUM_PLUGIN_PATH: $err"

# --- 5. run the scene --------------------------------------------------------------
step "stratum check / run $scene"
out=$("$stratum" check "$scene") || fail "stratum check $scene failed"
echo "   $out"
out=$("$stratum" run "$scene" --out "$work/out") || fail "stratum run $scene failed"
sed 's/^/   /' <<<"$out"
grep -q "^done: 1 steps" <<<"$out" || fail "stratum run did not report 'done: 1 steps'"
[[ -s $work/out/lame_kg.pvd ]] || fail "no $work/out/lame_kg.pvd"
ls "$work"/out/lame_kg_*.vtu >/dev/null 2>&1 || fail "no .vtu files in $work/out"

step "test_kg_elastic (material checks, Lamé u(a) against the closed form)"
if ! "$example_build/test_kg_elastic" "$scene" | sed 's/^/   /'; then
  fail "test_kg_elastic failed"
fi

# --- 6. a stage action and a mesh generator from out-of-tree plugins ------------------
staged=$example_src/lame_kg_staged.toml
step "stage action and mesh generator plugins: $staged"
grep -qx "stage_action example_cavity_pressure" "$plugin_dir/example_cavity_pressure.plugin" ||
  fail "the manifest example_cavity_pressure.plugin does not list 'stage_action example_cavity_pressure'"
grep -qx "mesh_generator example_ring" "$plugin_dir/example_ring_mesher.plugin" ||
  fail "the manifest example_ring_mesher.plugin does not list 'mesh_generator example_ring'"
out=$("$stratum" plugins --describe example_cavity_pressure) ||
  fail "stratum plugins --describe example_cavity_pressure failed"
grep -q "^stage_action example_cavity_pressure: " <<<"$out" || fail "the stage action is not described: $out"
out=$("$stratum" plugins --describe example_ring) || fail "stratum plugins --describe example_ring failed"
grep -q "^mesh_generator example_ring: " <<<"$out" || fail "the mesh generator is not described: $out"
grep -q "^  inner_radius  *number  *m " <<<"$out" || fail "example_ring's parameters are not described: $out"
out=$("$stratum" check "$staged") || fail "stratum check $staged failed"
echo "   $out"
out=$("$stratum" run "$staged" --out "$work/out_staged") || fail "stratum run $staged failed"
grep -q "^done: 1 steps" <<<"$out" || fail "stratum run $staged did not report 'done: 1 steps'"
# The action's own schema: a misspelt key is a located error with a suggestion.
sed 's/^p = 1.0$/pressure = 1.0/' "$staged" >"$work/bad_action.toml"
if err=$("$stratum" check "$work/bad_action.toml" 2>&1); then
  fail "stratum check accepted the unknown key 'pressure' in the example_cavity_pressure action"
fi
echo "   $err"
grep -q "bad_action.toml:[0-9]*:[0-9]*.*pressure" <<<"$err" || fail "the error does not name bad_action.toml:line:col and the key"
# The generator's own schema: a value out of range is located in [mesh.example_ring].
sed 's/^height = 0.5$/height = -0.5/' "$staged" >"$work/bad_mesh.toml"
if err=$("$stratum" check "$work/bad_mesh.toml" 2>&1); then
  fail "stratum check accepted height = -0.5 for example_ring"
fi
echo "   $err"
grep -q "bad_mesh.toml:[0-9]*:[0-9]*.*height" <<<"$err" || fail "the error does not name bad_mesh.toml:line:col and height"
if ! "$example_build/test_kg_elastic" "$staged" | sed 's/^/   /'; then
  fail "test_kg_elastic $staged failed"
fi

echo "sdk test passed"
