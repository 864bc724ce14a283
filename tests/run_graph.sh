#!/usr/bin/env bash
# run_graph.sh LOOM GRAPH OUT DATA: runs one example graph; exit 77 (skipped)
# for a *.coursedata.json graph when the course data folder is absent.
set -u
loom=$1 graph=$2 out=$3 data=$4
case "$graph" in
  *.coursedata.json) [ -d "$data" ] || { echo "course data absent: $data"; exit 77; } ;;
esac
rm -rf "$out" "$out.cache"
exec "$loom" run "$graph" --out "$out" --cache "$out.cache" --quiet
