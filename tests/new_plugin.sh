#!/usr/bin/env bash
# A new author's path, end to end: install Loom, `loom new-plugin`, then the
# three commands its README gives (configure+build, test, run), as written.
# Prints how long the scaffold-to-green path took.
set -euo pipefail
build=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
loom="$work/prefix/bin/loom"
start=$(date +%s.%N)

"$loom" new-plugin demo_fx --dir "$work" > "$work/scaffold.log"
cd "$work/demo_fx"
test -f README.md -a -f CMakeLists.txt -a -f plugin.cpp -a -f exposure.cpp -a -f tests/exposure_test.cpp
# The README's commands, taken from it rather than retyped here.
commands=$(sed -n '/^```$/,/^```$/p' README.md | grep -v '^```$')
test "$(echo "$commands" | wc -l)" -eq 3
while IFS= read -r command; do
  echo "+ $command"
  bash -euo pipefail -c "$command" > "$work/step.log" 2>&1 || { cat "$work/step.log"; exit 1; }
done <<< "$commands"
test -s out/exposure.png
end=$(date +%s.%N)

# The usual mistakes get clear answers.
if "$loom" new-plugin demo_fx --dir "$work" 2> "$work/again.log"; then exit 1; fi
grep -q "already exists" "$work/again.log"
if "$loom" new-plugin Bad-Name --dir "$work" 2> "$work/bad.log"; then exit 1; fi
grep -q "must start with a lowercase letter" "$work/bad.log"
if "$loom" new-plugin generate --dir "$work" 2> "$work/taken.log"; then exit 1; fi
grep -q "already on the plugin path" "$work/taken.log"
awk -v s="$start" -v e="$end" -v load="$(cut -d' ' -f1 /proc/loadavg)" \
  'BEGIN { printf "scaffold to green (configure+build, test, run): %.1f s (load %s)\n", e - s, load }'
