#!/usr/bin/env bash
# Runs a UI test program on a virtual display of its own: starts Xvfb on a
# free display (-displayfd: the server picks it, so parallel runs never share
# or kill each other's display), runs the program, stops the server.
# Exit 77 (ctest: skipped) with a message when Xvfb is missing.
set -euo pipefail
if ! command -v Xvfb >/dev/null; then
  echo "editor UI tests skipped: Xvfb is not installed (scripts/install-deps installs xvfb)"
  exit 77
fi
fifo_dir=$(mktemp -d)
trap 'kill "$xvfb" 2>/dev/null || true; wait "$xvfb" 2>/dev/null || true; rm -rf "$fifo_dir"' EXIT
# -noreset: the server outlives each test's window (a reset when the last
# client leaves refuses the next test's window for a moment).
Xvfb -displayfd 3 -screen 0 1600x1000x24 -nolisten tcp -noreset 3>"$fifo_dir/display" 2>"$fifo_dir/log" &
xvfb=$!
for _ in $(seq 1 100); do
  [ -s "$fifo_dir/display" ] && break
  sleep 0.1
done
if [ ! -s "$fifo_dir/display" ]; then
  echo "editor UI tests: Xvfb did not start:" >&2
  cat "$fifo_dir/log" >&2
  exit 1
fi
export DISPLAY=":$(head -n1 "$fifo_dir/display")"
# The same llvmpipe rasterizer everywhere.
export LIBGL_ALWAYS_SOFTWARE=1
"$@"
