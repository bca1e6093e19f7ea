#!/bin/sh
# The committed scene reference is the program's own: regenerates docs/scene-reference.md into a
# scratch file and compares. Usage: check.sh STRATUM_EXE SOURCE_DIR WORK_DIR
set -eu
exe=$1 src=$2 work=$3
mkdir -p "$work"
# Only the build tree's plugins (as in every test): no plugin from the environment.
env -u STRATUM_PLUGIN_PATH "$exe" describe --markdown > "$work/scene-reference.md"
if ! cmp -s "$work/scene-reference.md" "$src/docs/scene-reference.md"; then
  diff -u "$src/docs/scene-reference.md" "$work/scene-reference.md" | head -60 || true
  echo "docs/scene-reference.md is out of date (the schemas or the plugins changed); regenerate it with:"
  echo "  $exe describe --markdown > $src/docs/scene-reference.md"
  exit 1
fi
echo "docs/scene-reference.md is up to date"
