#!/usr/bin/env bash
# Installs Loom into a temporary prefix, builds plugins/example out of tree
# against it with find_package(loom), runs its tests and a graph with the installed loom
# and the new plugin: what a plugin author does.
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$source/plugins/example" -B "$work/example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/example" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
test -f "$work/example/lib/loom/plugins/libloom_example.loom.json"
# Its own GoogleTest test, written with loom::testing and registered by loom_add_plugin.
ctest --test-dir "$work/example" --output-on-failure > "$work/ctest.log" || { cat "$work/ctest.log"; exit 1; }
grep -q "100% tests passed" "$work/ctest.log"
cat > "$work/graph.json" <<'JSON'
{"loom": 1, "nodes": {
  "board": {"type": "Checkerboard", "inputs": {"size": [64, 64]}},
  "poster": {"type": "Posterize", "inputs": {"image": {"from": "board.image"}, "levels": 2}},
  "save": {"type": "SaveImage", "inputs": {"image": {"from": "poster.image"}, "path": "p.png"}}}}
JSON
# The installed loom must not see the build tree's plugins: only its own and the new one.
LOOM_PLUGIN_PATH="$work/example/lib/loom/plugins" "$work/prefix/bin/loom" run "$work/graph.json" \
  --out "$work/out" --profile "$work/profile.json"
test -s "$work/out/p.png"
grep -q '"example"' "$work/profile.json"
echo "out-of-tree plugin built and ran"
