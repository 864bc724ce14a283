#!/usr/bin/env bash
# run_graph.sh LOOM GRAPH OUT DATA: runs one example graph; exit 77 (skipped)
# for a *.coursedata.json graph when the course data folder is absent.
# A graph with a "time" range runs its first LOOM_TEST_FRAMES frames (default 4):
# this is a smoke test that every graph runs; the plugins' own tests check their
# simulations over many frames, and `loom run` runs the whole range.
set -u
loom=$1 graph=$2 out=$3 data=$4
case "$graph" in
  *.coursedata.json) [ -d "$data" ] || { echo "course data absent: $data"; exit 77; } ;;
esac
rm -rf "$out" "$out.cache"
frames=$(python3 -c '
import json, sys
t = json.load(open(sys.argv[1])).get("time")
if isinstance(t, dict):
    start, end = t.get("start", 1), t.get("end", t.get("start", 1))
    print("--frames %d-%d" % (start, min(end, start + int(sys.argv[2]) - 1)))
' "$graph" "${LOOM_TEST_FRAMES:-4}") || exit 1
exec "$loom" run "$graph" --out "$out" --cache "$out.cache" --quiet $frames
