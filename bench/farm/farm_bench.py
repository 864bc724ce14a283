"""Farm dispatch overhead and speed-up (docs/farm.md): on the local dispatcher
and on a private single-node Slurm cluster (tests/farm/slurm_cluster.py; root
only), the seconds from `loom submit` to the last task's end for
  - an empty task (one 8x8 image), against `loom run` of the same graph;
  - 8 one-frame tasks of that graph over 2 slots, against one `loom run` of
    its 8 frames: the cost of a task beyond its work is the difference over
    the 4 tasks each slot runs;
  - the 48 frames of graphs/time-twist-sequence.json in chunks of 1..48 frames
    over 2 slots, against one `loom run` of all 48 (medians of --repeats);
  - on Slurm, 8 tasks of `true` (an array of a shell script) over 2 slots:
    what Slurm itself costs a task, beside what Loom adds;
  - what one task pays by part (task_part rows: wall and CPU seconds of
    `loom --help`, `loom validate`, `loom run` without and with a cache, and
    `loom jobs task` against the `loom run` it runs; differences are parts).
Writes farm.csv and farm.png to --out (else $LOOM_BENCH_OUT, else bench/results).
Usage: farm_bench.py LOOM SOURCE_DIR [--quick] [--repeats N] [--out DIR]
(build/bin/bench_farm passes LOOM and SOURCE_DIR)."""
import argparse
import resource
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

parser = argparse.ArgumentParser(
    prog="bench_farm", description="loom submit: dispatch overhead per task and 48 frames in chunks, on the "
    "local dispatcher and a private single-node Slurm cluster (CSV and PNG).")
parser.add_argument("loom", help=argparse.SUPPRESS)
parser.add_argument("source", help=argparse.SUPPRESS)
parser.add_argument("--quick", action="store_true", help="chunks of 1, 12 and 48 only, one repeat")
parser.add_argument("--repeats", type=int, help="timings per measure, the median kept (default 3)")
parser.add_argument("--out", help="results folder (default: $LOOM_BENCH_OUT, else bench/results)")
ARGS = parser.parse_args()
LOOM, SOURCE, QUICK = ARGS.loom, ARGS.source, ARGS.quick
REPEATS = ARGS.repeats or (1 if QUICK else 3)
sys.path.insert(0, os.path.join(SOURCE, "tests", "farm"))
import slurm_cluster  # noqa: E402

TWIST = os.path.join(SOURCE, "graphs", "time-twist-sequence.json")


def timed(cmd, cluster=None):
    start = time.time()
    subprocess.run(cmd, check=True, capture_output=True, timeout=900)
    if cluster:
        cluster.wait_idle(600)
    return time.time() - start


def timed_cpu(cmd):
    """Wall and CPU (user + system of the children) seconds of cmd."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.time()
    subprocess.run(cmd, check=True, capture_output=True, timeout=900)
    wall = time.time() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def median(f):
    return statistics.median(f() for _ in range(REPEATS))


def empty_graph(folder, frames=1):
    g = {"loom": 1, "time": {"start": 1, "end": frames, "fps": 24}, "nodes": {
        "board": {"type": "Checkerboard", "inputs": {"size": [8, 8], "cells": 2}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "e_{frame}.png"}}}}
    path = os.path.join(folder, f"empty{frames}.json")
    with open(path, "w") as f:
        json.dump(g, f)
    return path


def submit(to, graph, out, cluster, *args):
    shutil.rmtree(out, ignore_errors=True)
    return timed([LOOM, "submit", graph, "--to", to, "--out", out, "-j", "2", "--no-cache", *args], cluster)


def measure(to, cluster, work, rows):
    empty = empty_graph(work)
    out = os.path.join(work, "o")
    rows.append(("empty_task", to, 1, median(lambda: submit(to, empty, out, cluster))))
    eight = empty_graph(work, 8)
    rows.append(("tasks8", to, 1, median(lambda: submit(to, eight, out, cluster, "--chunk", "1"))))
    print(f"{to}: 8 one-frame tasks: {rows[-1][3]:.2f} s", flush=True)
    if cluster:
        script = os.path.join(work, "true.sh")
        with open(script, "w") as f:
            f.write("#!/bin/sh\nexec true\n")
        rows.append(("true8", to, 1, median(
            lambda: timed(["sbatch", "--parsable", "--array=0-7", "-o", "/dev/null", script], cluster))))
        print(f"{to}: 8 tasks of true: {rows[-1][3]:.2f} s", flush=True)
    chunks = [1, 12, 48] if QUICK else [1, 2, 4, 6, 12, 24, 48]
    for chunk in chunks:
        # The video is left out: its assemble task would read every frame back.
        seconds = median(lambda: submit(to, TWIST, out, cluster, "--chunk", str(chunk), "--target", "frames"))
        rows.append(("twist48", to, chunk, seconds))
        print(f"{to}: 48 frames in chunks of {chunk}: {seconds:.2f} s", flush=True)


def task_parts(work, rows):
    """Each command's wall and CPU seconds, medians: docs/farm.md's table of
    what a task pays takes the differences."""
    empty, out, cache = empty_graph(work), os.path.join(work, "p"), os.path.join(work, "cache")
    submit("local", empty, out, None)
    task = json.load(open(os.path.join(out, ".loom-job", "manifest.json")))["tasks"][0]["args"]
    commands = {"help": [LOOM, "--help"], "validate": [LOOM, "validate", empty],
                "run": [LOOM, "run", empty, "--out", out, "--no-cache", "-q"],
                "run_cache": [LOOM, "run", empty, "--out", out, "--cache", cache, "-q"],
                "task_run": [LOOM, *task], "jobs_task": [LOOM, "jobs", "task", os.path.join(out, ".loom-job"), "0"]}
    for name, cmd in commands.items():
        runs = [timed_cpu(cmd) for _ in range(max(REPEATS, 5))]
        rows.append(("task_part_wall", name, 1, statistics.median(r[0] for r in runs)))
        rows.append(("task_part_cpu", name, 1, statistics.median(r[1] for r in runs)))
        print(f"{name}: {rows[-2][3]:.3f} s wall, {rows[-1][3]:.3f} s CPU", flush=True)


def main():
    work = tempfile.mkdtemp(prefix="loom-farm-bench-")
    os.chmod(work, 0o755)
    rows = []
    empty, out = empty_graph(work), os.path.join(work, "r")
    rows.append(("empty_task", "loom run", 1,
                 median(lambda: timed([LOOM, "run", empty, "--out", out, "--no-cache", "-q"]))))
    rows.append(("twist48", "loom run", 48, median(lambda: timed(
        [LOOM, "run", TWIST, "--out", out, "--no-cache", "-q", "--target", "frames"]))))
    print(f"one loom run of 48 frames: {rows[-1][3]:.2f} s", flush=True)
    rows.append(("tasks8", "loom run", 8, median(lambda: timed(
        [LOOM, "run", empty_graph(work, 8), "--out", out, "--no-cache", "-q"]))))
    task_parts(work, rows)
    measure("local", None, work, rows)
    reason = slurm_cluster.unavailable_reason()
    if reason:
        print(f"note: no Slurm measurements: {reason}")
    else:
        cluster = slurm_cluster.SlurmCluster()
        try:
            cluster.start()
            measure("slurm", cluster, work, rows)
        finally:
            cluster.stop()
    shutil.rmtree(work, ignore_errors=True)
    results = ARGS.out or os.environ.get("LOOM_BENCH_OUT", os.path.join(SOURCE, "bench", "results"))
    os.makedirs(results, exist_ok=True)
    load = os.getloadavg()[0]
    csv = os.path.join(results, "farm.csv")
    with open(csv + ".tmp", "w") as f:
        f.write(f"# load average {load:.2f} on {os.cpu_count()} cores; medians of {REPEATS}\n")
        f.write("measure,dispatcher,chunk,seconds\n")
        f.writelines(f"{m},{d},{c},{s:.3f}\n" for m, d, c, s in rows)
    os.replace(csv + ".tmp", csv)
    plot(results, rows)
    print(f"wrote {csv} (load average {load:.2f})")


def plot(results, rows):
    if not shutil.which("gnuplot"):
        print("note: gnuplot not found, no plot (apt-get install gnuplot-nox)")
        return
    single = next(s for m, d, c, s in rows if m == "twist48" and d == "loom run")
    script = ["set terminal pngcairo size 800,560 noenhanced", f"set output '{results}/farm.png.tmp'",
              "set logscale x 2", "set grid", "set xlabel 'frames per task (48 frames, 2 slots)'",
              "set ylabel 'seconds, submit to last task'", "set title 'loom submit: chunk size against wall time'"]
    series = [d for d in ("local", "slurm") if any(r[1] == d for r in rows)]
    plots = [f"'-' using 1:2 with linespoints pointtype 7 title '{d}'" for d in series]
    plots.append(f"{single} title 'one loom run' with lines dashtype 2")
    script.append("plot [0.8:60] " + ", ".join(plots))
    for d in series:
        script += [f"{c} {s}" for m, dd, c, s in rows if m == "twist48" and dd == d] + ["e"]
    subprocess.run(["gnuplot"], input="\n".join(script) + "\n", text=True, check=True)
    os.replace(f"{results}/farm.png.tmp", f"{results}/farm.png")


if __name__ == "__main__":
    main()
