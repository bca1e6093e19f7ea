#!/usr/bin/env bash
# The plugin SDK test (CTest: sdk.out_of_tree_plugin).
#
#   run.sh <stratum build dir> <tests/sdk dir> <work dir>
#
# 1. installs the built framework into <work>/prefix (headers, libstratum, the
#    in-tree plugins, the CMake package config, the stratum program), and checks
#    that the installed program searches only installed plugins, never the build
#    tree's (`stratum plugins --paths`; a plugin removed from the prefix is gone);
# 2. writes out the code blocks of docs/plugin-guide.md that start with a
#    `// file: NAME` / `# file: NAME` marker (tools/guide_snippets.py), checks
#    its `excerpt of:` blocks against the source tree, and configures and builds
#    every project among them (each folder with a CMakeLists.txt) against that
#    prefix only (find_package(Stratum) + stratum_add_plugin), with -Werror;
# 3. checks that the installed stratum finds its own plugins and, through
#    STRATUM_PLUGIN_PATH, the guide's example plugin (`stratum plugins --describe`);
# 4. checks that the schema's range reaches the user as a located error;
# 5. `stratum check` and `stratum run --out` every scene (*.toml) of the guide:
#    each must state [[checks]] and pass them (the Lamé cylinder's u(a), u(b)
#    against the closed form); then runs the projects' own tests (ctest), i.e.
#    the guide's test program test_kg_elastic;
#    two_layer_flow.toml runs the guide's scalar-field element (example_diffusion) against
#    the closed form of steady two-layer flow;
# 6. the stage action and mesh generator plugins of the guide (lame_kg_staged.toml, run in
#    step 5): manifests, descriptions, and their own schemas' located errors;
# 7. the guide's calibration target: `stratum fit example_kg_elastic kg_triaxial.csv` gives back
#    the K and G the curves were made from; a misspelt target gets the nearest name.
# Exits non-zero with a message naming the failed check.
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 <stratum build dir> <tests/sdk dir> <work dir>" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
sdk=$(cd "$2" && pwd)
work=$3
source_root=$(cd "$sdk/../.." && pwd)
# The guide whose code is built; STRATUM_SDK_GUIDE may name another (a draft of a new section).
guide=${STRATUM_SDK_GUIDE:-$source_root/docs/plugin-guide.md}

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
example_src=$work/guide # the files written out of the guide
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

stratum=$prefix/bin/stratum

# --- 1b. the installed program never looks in the build tree ----------------------
step "the installed stratum searches only installed plugins"
paths=$(env -u STRATUM_PLUGIN_PATH "$stratum" plugins --paths) || fail "stratum plugins --paths failed"
sed 's/^/   | /' <<<"$paths"
[[ $(realpath -m "$(head -n 1 <<<"$paths")") == "$(realpath "$libdir/stratum/plugins")" ]] ||
  fail "the installed stratum does not search $libdir/stratum/plugins first:"$'\n'"$paths"
while IFS= read -r d; do
  if [[ $(realpath -m "$d") == "$(realpath "$build")/plugins" ]]; then
    fail "the installed stratum searches the build tree's plugins $build/plugins:"$'\n'"$paths"
  fi
done <<<"$paths"
paths=$(STRATUM_PLUGIN_PATH=/nowhere/a:/nowhere/b "$stratum" plugins --paths)
[[ $paths == "/nowhere/a"$'\n'"/nowhere/b"$'\n'* ]] || fail "STRATUM_PLUGIN_PATH does not come first:"$'\n'"$paths"
# A plugin taken out of the prefix is gone for the installed program, although the build tree
# (on no path) still has it.
[[ -f $build/plugins/stratum_von_mises.plugin ]] || fail "the build tree has no von_mises plugin to compare with"
rm -f "$libdir/stratum/plugins/stratum_von_mises.so" "$libdir/stratum/plugins/stratum_von_mises.plugin"
if err=$(env -u STRATUM_PLUGIN_PATH "$stratum" plugins --describe von_mises 2>&1); then
  fail "the installed stratum still found von_mises after its removal from the prefix:"$'\n'"$err"
fi
echo "   von_mises removed from the prefix: $err"

# --- 2. write out the guide's files and build them against the installed package --
step "the guide's code: $guide -> $example_src"
command -v python3 >/dev/null 2>&1 || fail "python3 is needed to read the guide's code blocks"
run_logged "$work/extract.log" python3 "$source_root/tools/guide_snippets.py" "$guide" "$example_src" \
  --source "$source_root"
sed 's/^/   /' "$work/extract.log"
# Every folder with a CMakeLists.txt is a project of its own, unless a project above it takes it
# in with add_subdirectory(<its path>).
projects=()
while IFS= read -r f; do
  d=$(dirname "$f")
  inner=0
  for p in "${projects[@]}"; do
    if [[ $d == "$p"/* ]] && grep -Eq "add_subdirectory\([[:space:]]*\"?${d#"$p"/}\"?[[:space:])]" "$p/CMakeLists.txt"; then
      inner=1
    fi
  done
  ((inner)) || projects+=("$d")
done < <(find "$example_src" -name CMakeLists.txt | awk '{ print length($0) " " $0 }' | sort -n | cut -d' ' -f2-)
((${#projects[@]})) || fail "the guide has no '# file: CMakeLists.txt' block"
[[ -f $scene ]] || fail "the guide has no '# file: lame_kg.toml' block"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
compiler=()
[[ -n $cxx ]] && compiler=(-DCMAKE_CXX_COMPILER="$cxx")
builds=()
for p in "${projects[@]}"; do
  rel=${p#"$example_src"}
  b=$example_build$rel
  log=$work/build${rel//\//_}
  step "build guide project ${rel:-/} against $prefix"
  # -Werror: the guide's code must compile cleanly, as its readers' projects will.
  run_logged "$log.configure.log" cmake "${generator[@]}" -S "$p" -B "$b" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_FLAGS=-Werror "${compiler[@]}"
  grep -q "Stratum_DIR:PATH=$libdir/cmake/Stratum" "$b/CMakeCache.txt" ||
    fail "find_package(Stratum) did not pick the installed package ($(grep '^Stratum_DIR' "$b/CMakeCache.txt"))"
  run_logged "$log.log" cmake --build "$b"
  builds+=("$b")
done
plugin_dir=$example_build/plugins
[[ -f $plugin_dir/example_kg_elastic.so ]] || fail "no $plugin_dir/example_kg_elastic.so"
grep -qx "material example_kg_elastic" "$plugin_dir/example_kg_elastic.plugin" ||
  fail "the manifest $plugin_dir/example_kg_elastic.plugin does not list 'material example_kg_elastic'"
echo "   built example_kg_elastic.so, its manifest and test_kg_elastic"

# Only the guide's plugin folders on the search path: everything else must come from the install.
plugin_path=$(find "$example_build" -name '*.plugin' -printf '%h\n' | sort -u | paste -sd:)
export STRATUM_PLUGIN_PATH=$plugin_path

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

# --- 5. run the guide's scenes: each states [[checks]] and passes them --------------
while IFS= read -r s; do
  name=$(basename "$s" .toml)
  step "stratum check / run ${s#"$example_src"/}"
  out=$("$stratum" check "$s") || fail "stratum check $s failed"
  echo "   $out"
  grep -q '^\[\[checks\]\]' "$s" || fail "the guide's scene $s states no [[checks]]"
  code=0
  out=$("$stratum" run "$s" --out "$work/out/$name") || code=$?
  sed 's/^/   /' <<<"$out"
  ((code == 0)) || fail "stratum run $s exited with status $code"
  grep -q "^check .*: pass$" <<<"$out" || fail "stratum run $s printed no passed check"
  if grep -q "^check .*: FAIL$" <<<"$out"; then fail "a check of $s failed"; fi
done < <(find "$example_src" -name '*.toml' | sort)
[[ -s $work/out/lame_kg/lame_kg.pvd ]] || fail "no $work/out/lame_kg/lame_kg.pvd"
ls "$work"/out/lame_kg/lame_kg_*.vtu >/dev/null 2>&1 || fail "no .vtu files in $work/out/lame_kg"
# The scalar-field element: the scene ran above with its three checks (the closed form to 1e-10);
# its head is written as the VTK point array "h [m]" (the field's unit, as every array names it).
[[ -f $example_src/two_layer_flow.toml ]] || fail "the guide writes no two_layer_flow.toml"
grep -qx "element example_diffusion" "$plugin_dir/example_diffusion.plugin" ||
  fail "the manifest example_diffusion.plugin does not list 'element example_diffusion'"
grep -lq 'Name="h \[m\]"' "$work"/out/two_layer_flow/two_layer_flow_*.vtu ||
  fail "the VTK output of two_layer_flow.toml has no point array 'h [m]'"
echo "   two_layer_flow: the head h of example_diffusion at the closed form, and in the VTK files"

step "the guide's tests (ctest): test_kg_elastic, material checks and Lamé u(a) against the closed form"
for b in "${builds[@]}"; do
  run_logged "$work/ctest.log" ctest --test-dir "$b" --output-on-failure
done
[[ -x $example_build/test_kg_elastic ]] || fail "the guide's project built no test_kg_elastic"
if ! "$example_build/test_kg_elastic" "$scene" | sed 's/^/   /'; then
  fail "test_kg_elastic failed"
fi

# --- 6. a stage action and a mesh generator from out-of-tree plugins ------------------
staged=$example_src/lame_kg_staged.toml
[[ -f $staged ]] || fail "the guide writes no lame_kg_staged.toml"
step "stage action and mesh generator plugins: $staged"
grep -qx "stage_action example_cavity_pressure" "$plugin_dir/example_cavity_pressure.plugin" ||
  fail "the manifest example_cavity_pressure.plugin does not list 'stage_action example_cavity_pressure'"
grep -qx "mesh_generator example_ring" "$plugin_dir/example_ring_mesher.plugin" ||
  fail "the manifest example_ring_mesher.plugin does not list 'mesh_generator example_ring'"
out=$(STRATUM_PLUGIN_PATH=$plugin_path "$stratum" plugins --describe example_cavity_pressure) ||
  fail "stratum plugins --describe example_cavity_pressure failed"
grep -q "^stage_action example_cavity_pressure: " <<<"$out" || fail "the stage action is not described: $out"
out=$(STRATUM_PLUGIN_PATH=$plugin_path "$stratum" plugins --describe example_ring) ||
  fail "stratum plugins --describe example_ring failed"
grep -q "^mesh_generator example_ring: " <<<"$out" || fail "the mesh generator is not described: $out"
grep -q "^  inner_radius  *number  *m " <<<"$out" || fail "example_ring's parameters are not described: $out"
# The action's own schema: a misspelt key is a located error with a suggestion.
sed 's/^p = 1.0$/pressure = 1.0/' "$staged" >"$work/bad_action.toml"
if err=$(STRATUM_PLUGIN_PATH=$plugin_path "$stratum" check "$work/bad_action.toml" 2>&1); then
  fail "stratum check accepted the unknown key 'pressure' in the example_cavity_pressure action"
fi
echo "   $err"
grep -q "bad_action.toml:[0-9]*:[0-9]*.*pressure" <<<"$err" || fail "the error does not name bad_action.toml:line:col and the key"
# The generator's own schema: a value out of range is located in [mesh.example_ring].
sed 's/^height = 0.5$/height = -0.5/' "$staged" >"$work/bad_mesh.toml"
if err=$(STRATUM_PLUGIN_PATH=$plugin_path "$stratum" check "$work/bad_mesh.toml" 2>&1); then
  fail "stratum check accepted height = -0.5 for example_ring"
fi
echo "   $err"
grep -q "bad_mesh.toml:[0-9]*:[0-9]*.*height" <<<"$err" || fail "the error does not name bad_mesh.toml:line:col and height"

# --- 7. a calibration target from an out-of-tree plugin: stratum fit ------------------
step "calibration target: stratum fit example_kg_elastic kg_triaxial.csv"
grep -qx "calibration example_kg_elastic" "$plugin_dir/example_kg_fit.plugin" ||
  fail "the manifest example_kg_fit.plugin does not list 'calibration example_kg_elastic'"
curves=$example_src/kg_triaxial.csv
[[ -f $curves ]] || fail "the guide writes no kg_triaxial.csv"
out=$("$stratum" fit example_kg_elastic "$curves") || fail "stratum fit example_kg_elastic failed"
sed 's/^/   | /' <<<"$out"
# the solid of the curves: K = 1000 kPa, G = 600 kPa (E = 1500 kPa, nu = 0.25)
grep -qx "K = 1000.0" <<<"$out" || fail "stratum fit example_kg_elastic did not give K = 1000.0"
grep -qx "G = 600.0" <<<"$out" || fail "stratum fit example_kg_elastic did not give G = 600.0"
# the installed targets are listed beside it, a misspelt one gets the nearest name
if err=$("$stratum" fit example_kg_elastc "$curves" 2>&1); then
  fail "stratum fit accepted the unknown target example_kg_elastc"
fi
echo "   $err"
grep -q "unknown target 'example_kg_elastc'; allowed: .*duncan_chang.*example_kg_elastic.*did you mean 'example_kg_elastic'" <<<"$err" ||
  fail "the unknown-target error does not list the targets and the nearest name: $err"

echo "sdk test passed"
