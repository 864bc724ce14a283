#!/usr/bin/env bash
# Plugin hot reload as a plugin author meets it: install Loom, scaffold a
# plugin with `loom new-plugin`, build it with its own CMake, then run the
# editor's hot-reload test (EditorHotReload.*), which edits the plugin's
# source and rebuilds it with that CMake while the editor runs.
set -euo pipefail
build=$1
tests=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
"$work/prefix/bin/loom" new-plugin hotfx --dir "$work" > "$work/scaffold.log"
cmake -S "$work/hotfx" -B "$work/hotfx/build" -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log" 2>&1 \
  || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/hotfx/build" --target loom_hotfx > "$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
export LOOM_HOT_RELOAD_PLUGIN="$work/hotfx"
"$(dirname "$0")/run_under_xvfb.sh" "$tests" --gtest_filter='EditorHotReload.*'
