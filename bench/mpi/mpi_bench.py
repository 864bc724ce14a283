"""`loom run` over MPI ranks (docs/farm.md, "MPI"): on the Cornell box
(graphs/pathtrace-cornell-box.json's blocks), medians of --repeats, the
configurations alternated so that the machine's load spoils them alike:
  - distribution: 1 rank x 2 threads against 2 ranks x 1 thread (and 1 rank x
    1 thread: the per-sample cost), wall time of the command;
  - gather: a 3840x2160 float RGB image (Checkerboard -> Posterize, split in
    tiles) gathered on rank 0, and on every rank (a second Posterize reads
    it), on 2 and 4 ranks, as `loom` reports it, against the bytes that cross
    between ranks at this machine's copy bandwidth (memcpy of the image
    between two buffers already touched, measured in the same run);
  - imbalance: the static split's slowest rank's time in PathTrace over the
    mean, for tile edges 8..128 on 2 and 4 ranks;
  - uneven: 3 ranks, rank 2 held to half speed, tiles dealt statically and
    dynamically, then sample passes (--mpi-split samples) the same:
    PathTrace's time on the slowest rank over what the ranks' measured
    speeds would need if the work were shared in proportion;
  - uneven-frames, uneven-points: the same for 48 frames of a twisting warp
    (graphs/time-twist-sequence.json at 768x768, --threads 1), and for a
    sweep of 48 points of its first frame, blocks / round-robin against dealt as ranks
    ask: the slowest rank's time in its frames (points) over the ideal, and
    the command's wall time;
  - startup: mpiexec's start-up, 4 ranks of a one-node graph against one `loom run`.
Writes mpi.csv and mpi.png to --out (else $LOOM_BENCH_OUT, else bench/results).
Usage: mpi_bench.py LOOM SOURCE_DIR [--quick] [--repeats N] [--only MEASURE,...] [--out DIR]."""
import argparse
import csv
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

parser = argparse.ArgumentParser(prog="bench_mpi", description=__doc__.split("\n")[0])
parser.add_argument("loom", help=argparse.SUPPRESS)
parser.add_argument("source", help=argparse.SUPPRESS)
parser.add_argument("--quick", action="store_true", help="smaller image and fewer samples, one repeat")
parser.add_argument("--repeats", type=int, help="timings per measure, the median kept (default 3)")
parser.add_argument("--out", help="results folder (default: $LOOM_BENCH_OUT, else bench/results)")
parser.add_argument("--only", default="distribution,gather,imbalance,uneven,uneven-frames,uneven-points,startup",
                    help="measures to take, comma-separated (default: all)")
ARGS = parser.parse_args()
LOOM, SOURCE, QUICK = ARGS.loom, ARGS.source, ARGS.quick
REPEATS = ARGS.repeats or (1 if QUICK else 3)
OUT = ARGS.out or os.environ.get("LOOM_BENCH_OUT") or os.path.join(SOURCE, "bench", "results")
ONLY = ARGS.only.split(",")
MPIEXEC = shutil.which("mpiexec")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
# Shared memory with its single copy (CMA) where the kernel allows it, loopback only.
MPI_ARGS = ["--oversubscribe", "--bind-to", "none", "--mca", "btl", "self,vader", "--mca", "oob_tcp_if_include", "lo"]
SIZE, SPP = ([128, 128], 16) if QUICK else ([256, 256], 64)


def write(folder, name, nodes):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump({"loom": 1, "seed": 13, "nodes": nodes}, f)
    return path


def command(ranks, threads, *args):
    run = [LOOM, "run", *map(str, args), "--threads", str(threads), "--no-cache"]
    return run if ranks == 0 else [MPIEXEC, "-n", str(ranks), *MPI_ARGS, *run]


def timed(cmd):
    start = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1800, env=ENV)
    if p.returncode != 0:
        sys.exit(f"bench_mpi: {' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
    return time.time() - start, p.stderr


def alternate(configs):
    """{name: [seconds...]} with every configuration run once per round."""
    times = {name: [] for name in configs}
    logs = {name: [] for name in configs}
    for _ in range(REPEATS):
        for name, cmd in configs.items():
            t, err = timed(cmd)
            times[name].append(t)
            logs[name].append(err)
    return times, logs


def copy_bandwidth(nbytes):
    """Bytes per second of one memcpy between two buffers already touched, the
    median of 5 (CPython copies a bytearray slice with memcpy)."""
    src = bytearray(b"\x01") * nbytes
    dst = bytearray(nbytes)
    dst[:] = src  # first touch of dst's pages: not what is measured
    seconds = []
    for _ in range(5):
        start = time.perf_counter()
        dst[:] = src
        seconds.append(time.perf_counter() - start)
    return nbytes / statistics.median(seconds)


def measure_distribution(tmp, box, out, rows):
    times, _ = alternate({"1 rank x 1 thread": command(0, 1, box, "--out", out),
                          "1 rank x 2 threads": command(0, 2, box, "--out", out),
                          "2 ranks x 1 thread": command(2, 1, box, "--out", out, "--mpi-tile", 16)})
    paths = SIZE[0] * SIZE[1] * SPP
    for name, ts in times.items():
        rows.append({"measure": "cornell box " + name, "seconds": statistics.median(ts),
                     "detail": f"{SIZE[0]}x{SIZE[1]} at {SPP} spp"})
    one = statistics.median(times["1 rank x 1 thread"])
    rows.append({"measure": "seconds per path, 1 thread (whole command)", "seconds": one / paths, "detail": ""})
    rows.append({"measure": "ratio 2 ranks x 1 thread / 1 rank x 2 threads",
                 "seconds": statistics.median(times["2 ranks x 1 thread"]) /
                 statistics.median(times["1 rank x 2 threads"]), "detail": "ratio"})


def measure_gather(tmp, out, rows):
    """poster is gathered on every rank (poster2, split after it, reads it),
    poster2 on rank 0 alone; each against the bytes that cross between ranks,
    (N-1)/N of the image to each receiving rank, at the copy bandwidth."""
    width, height = 3840, 2160
    image_bytes = width * height * 3 * 4
    big = write(tmp, "big.json", {
        "board": {"type": "Checkerboard", "inputs": {"size": [width, height], "cells": 27}},
        "poster": {"type": "Posterize", "inputs": {"image": {"from": "board.image"}, "levels": 3}},
        "poster2": {"type": "Posterize", "inputs": {"image": {"from": "poster.image"}, "levels": 2}}})
    bandwidth = copy_bandwidth(image_bytes)
    rows.append({"measure": "memcpy of the image, buffers already touched", "seconds": image_bytes / bandwidth,
                 "detail": f"{bandwidth / 1e9:.2f} GB/s"})
    for ranks in (2, 4):
        gathers = {"poster": [], "poster2": []}
        for _ in range(REPEATS):
            _, err = timed(command(ranks, 1, big, "--out", out, "--target", "poster2.image", "-q"))
            for node in gathers:
                gathers[node].append(float(re.search(rf"mpi: {node}: .* in ([0-9.]+) s", err).group(1)))
        for node, receivers in (("poster2", 1), ("poster", ranks)):
            seconds = statistics.median(gathers[node])
            moved = image_bytes * (ranks - 1) / ranks * receivers
            where = "rank 0" if receivers == 1 else "every rank"
            rows.append({"measure": f"gather 3840x2160 float RGB to {where}, {ranks} ranks", "seconds": seconds,
                         "detail": f"{moved / 1e6:.1f} MB between ranks: {seconds / (moved / bandwidth):.1f}x "
                                   "their memcpy"})


def measure_imbalance(tmp, box, out, rows):
    for ranks in (2, 4):
        for tile in (8, 16, 32, 64, 128):
            imbalance = []
            for _ in range(REPEATS):
                _, err = timed(command(ranks, 1, box, "--out", out, "--mpi-tile", tile))
                imbalance.append(float(re.search(r"mpi: trace: .*imbalance ([0-9.]+)", err).group(1)))
            rows.append({"measure": f"imbalance {ranks} ranks tile {tile}", "seconds": statistics.median(imbalance),
                         "detail": "slowest / mean rank time"})


def rank_pid(launcher, rank, timeout=60):
    """The PID of `rank` among the processes that mpiexec `launcher` started."""
    deadline = time.time() + timeout
    while time.time() < deadline and launcher.poll() is None:
        for pid in filter(str.isdigit, os.listdir("/proc")):
            try:
                with open(f"/proc/{pid}/environ", "rb") as f:
                    env = f.read().split(b"\0")
                with open(f"/proc/{pid}/stat") as f:
                    parent = int(f.read().rsplit(")", 1)[1].split()[1])
            except OSError:
                continue
            if parent == launcher.pid and f"OMPI_COMM_WORLD_RANK={rank}".encode() in env:
                return int(pid)
        time.sleep(0.05)
    return None


def half_speed_run(cmd):
    """Runs cmd (mpiexec) with rank 2 held to half speed: stopped 50 ms of
    every 100 ms (SIGSTOP/SIGCONT), which slows it alone on any number of
    cores (pinning it to a core shared with a busy process would, on 2
    cores, share the others' cores too). Returns stderr and the wall time."""
    start = time.time()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    slow = rank_pid(p, 2)

    def duty_cycle():
        while slow and p.poll() is None:
            try:
                os.kill(slow, signal.SIGSTOP)
                time.sleep(0.05)
                os.kill(slow, signal.SIGCONT)
                time.sleep(0.05)
            except ProcessLookupError:
                return
    threading.Thread(target=duty_cycle, daemon=True).start()
    _, err = p.communicate(timeout=1800)
    if slow:
        try:
            os.kill(slow, signal.SIGCONT)
        except ProcessLookupError:
            pass
    if p.returncode != 0:
        sys.exit(f"bench_mpi: {' '.join(cmd)}: exit {p.returncode}\n{err}")
    return err, time.time() - start


def against_even_sharing(err, deal):
    """PathTrace's time on the slowest rank over the time the ranks' measured
    speeds would need for the whole if it were shared in proportion to them:
    rank r did a share w_r of the tiles in t_r seconds, so its speed is
    w_r / t_r and the ideal is 1 / sum(w_r / t_r). Static shares are a third
    each (interleaved tiles, imbalance 1.00-1.06 on equal ranks); dealt ones
    are the parts each rank took."""
    seconds = [float(x) for x in re.search(r"mpi: trace: tiles computed .*ranks 0\.\.2: ([0-9. ]+) s", err)
               .group(1).split()]
    if deal == "dynamic":
        m = re.search(r"mpi: trace: (\d+) parts dealt as ranks asked: (\d+), (\d+), (\d+)", err)
        shares = [int(c) / int(m.group(1)) for c in m.groups()[1:]]
    else:
        shares = [1 / 3] * 3
    ideal = 1 / sum(w / t for w, t in zip(shares, seconds))
    return max(seconds) / ideal, seconds, shares


def against_even_sharing_of_samples(err):
    """As against_even_sharing, split by samples (rank 0's line "mpi: trace:
    samples ... in P passes: n0, n1, n2 to ranks 0..2 (busy b0, b1, b2 s of T
    s)"): rank r took a share w_r of the samples in b_r seconds of its own
    work (its waits for the others at each pass's sum left out), so the ideal
    is 1 / sum(w_r / b_r); every pass ends in a sum that waits for the
    slowest rank, so every rank's time is T, from its first pass to the end
    of its last sum (the sums' own cost included)."""
    m = re.search(r"mpi: trace: samples .* in (\d+) pass(?:es)?: ([0-9, ]+) to ranks 0\.\.2 "
                  r"\(busy ([0-9., ]+) s of ([0-9.]+) s\)", err)
    taken = [int(c) for c in m.group(2).split(", ")]
    busy = [float(b) for b in m.group(3).split(", ")]
    shares = [c / sum(taken) for c in taken]
    ideal = 1 / sum(w / t for w, t in zip(shares, busy) if w > 0)
    return float(m.group(4)) / ideal, busy, shares, int(m.group(1))


def measure_uneven(tmp, box, out, rows):
    """Tiles (of 16 px), then sample passes (--mpi-split samples), static
    against dealt, alternated."""
    splits = {"tiles": ["--mpi-tile", 16], "samples": ["--mpi-split", "samples"]}
    for split, args in splits.items():
        results = {deal: ([], []) for deal in ("static", "dynamic")}
        for _ in range(REPEATS):
            for deal, (ratios, details) in results.items():
                err, wall = half_speed_run(command(3, 1, box, "--out", out, *args, "--mpi-deal", deal))
                if split == "tiles":
                    ratio, seconds, shares = against_even_sharing(err, deal)
                    passes = ""
                else:
                    ratio, seconds, shares, count = against_even_sharing_of_samples(err)
                    passes = f", {count} passes"
                ratios.append(ratio)
                details.append("PathTrace on ranks 0..2 " + " ".join(f"{t:.1f}" for t in seconds) + " s, shares " +
                               " ".join(f"{w:.2f}" for w in shares) + f"{passes}, command {wall:.1f} s")
        for deal, (ratios, details) in results.items():
            median = statistics.median(ratios)
            rows.append({"measure": f"3 ranks, rank 2 at half speed, {deal} {split}: slowest / even sharing",
                         "seconds": median, "detail": details[ratios.index(median)] if median in ratios else ""})


def against_even_sharing_of(err, what, count, deal):
    """As against_even_sharing, for frames or sweep points: rank r's seconds
    in its items (rank 0's "mpi: frames computed in ..." line), and its share:
    static, frames in contiguous blocks (count * r // 3 ...), points
    round-robin; dealt, the items it took."""
    seconds = [float(x) for x in re.search(rf"mpi: {what} computed .*ranks 0\.\.2: ([0-9. ]+) s", err)
               .group(1).split()]
    if deal == "dynamic":
        m = re.search(rf"mpi: {count} {what} dealt as ranks asked: (\d+), (\d+), (\d+)", err)
        taken = [int(c) for c in m.groups()]
    elif what == "frames":
        taken = [count * (r + 1) // 3 - count * r // 3 for r in range(3)]
    else:
        taken = [len(range(r, count, 3)) for r in range(3)]
    shares = [c / count for c in taken]
    ideal = 1 / sum(w / t for w, t in zip(shares, seconds) if w > 0)
    return max(seconds) / ideal, seconds, taken


def measure_uneven_items(tmp, out, rows, what):
    """48 frames, or 48 sweep points of frame 1 (the checkerboard's cells
    swept), of the twisting warp at 768x768 (0.2-0.3 s a frame with its PNG
    on a free core), 3 ranks of 1 thread, rank 2 at half speed, static
    against dealt, alternated."""
    count = 48
    twist = [os.path.join(SOURCE, "graphs", "time-twist-sequence.json"), "--out", out, "--set",
             "board.size=[768,768]", "--target", "frames"]
    items = ["--frames", f"1-{count}"] if what == "frames" else \
        ["--frames", "1", "--sweep", f"board.cells=2:{count + 1}:{count}"]
    results = {deal: ([], [], []) for deal in ("static", "dynamic")}
    for _ in range(REPEATS):
        for deal, (ratios, walls, details) in results.items():
            err, wall = half_speed_run(command(3, 1, *twist, *items, "--mpi-deal", deal))
            ratio, seconds, taken = against_even_sharing_of(err, what, count, deal)
            ratios.append(ratio)
            walls.append(wall)
            details.append(f"{what} on ranks 0..2 " + " ".join(f"{t:.1f}" for t in seconds) + " s, taken " +
                           " ".join(map(str, taken)) + f", command {wall:.1f} s")
    for deal, (ratios, walls, details) in results.items():
        median = statistics.median(ratios)
        rows.append({"measure": f"3 ranks, rank 2 at half speed, {deal} {what}: slowest / even sharing",
                     "seconds": median, "detail": details[ratios.index(median)] if median in ratios else ""})
        rows.append({"measure": f"3 ranks, rank 2 at half speed, {deal} {what}: command wall",
                     "seconds": statistics.median(walls), "detail": "seconds"})


def measure_startup(tmp, out, rows):
    tiny = write(tmp, "tiny.json", {"v": {"type": "Math", "inputs": {"a": 1, "b": 2, "op": "add"}}})
    times, _ = alternate({"loom run": command(0, 1, tiny, "--out", out, "--target", "v.result"),
                          "mpiexec -n 4 loom run": command(4, 1, tiny, "--out", out, "--target", "v.result")})
    for name, ts in times.items():
        rows.append({"measure": "start-up: " + name + " of a one-node graph", "seconds": statistics.median(ts),
                     "detail": ""})


def main():
    if not MPIEXEC:
        print("bench_mpi: skipped: mpiexec is not installed (openmpi-bin)")
        sys.exit(77)
    os.makedirs(OUT, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="loom-bench-mpi-")
    rows = []
    load = open("/proc/loadavg").read().split()[0]
    box = write(tmp, "box.json", {
        "box": {"type": "CornellBox", "inputs": {"contents": "blocks"}},
        "trace": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}, "size": SIZE, "spp": SPP,
                                                  "max_depth": 8}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "trace.image"}, "path": "box.exr"}}})
    out = os.path.join(tmp, "out")
    if "distribution" in ONLY:
        measure_distribution(tmp, box, out, rows)
    if "gather" in ONLY:
        measure_gather(tmp, out, rows)
    if "imbalance" in ONLY:
        measure_imbalance(tmp, box, out, rows)
    if "uneven" in ONLY:
        measure_uneven(tmp, box, out, rows)
    if "uneven-frames" in ONLY:
        measure_uneven_items(tmp, out, rows, "frames")
    if "uneven-points" in ONLY:
        measure_uneven_items(tmp, out, rows, "sweep points")
    if "startup" in ONLY:
        measure_startup(tmp, out, rows)

    csv_path = os.path.join(OUT, "mpi.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["measure", "seconds", "detail", "load"])
        w.writeheader()
        for r in rows:
            w.writerow({**r, "load": load})
    for r in rows:
        print(f"{r['measure']:55s} {r['seconds']:.6g} {r['detail']}")
    print(f"load average at the start: {load}, at the end: {open('/proc/loadavg').read().split()[0]}; {csv_path}")
    if "imbalance" in ONLY:
        plot(rows)
    shutil.rmtree(tmp, ignore_errors=True)


def plot(rows):
    """Imbalance against tile edge, one line per rank count (gnuplot, as the other benchmarks)."""
    data = os.path.join(OUT, "mpi_imbalance.dat")
    with open(data, "w") as f:
        for ranks in (2, 4):
            for r in rows:
                m = re.match(rf"imbalance {ranks} ranks tile (\d+)", r["measure"])
                if m:
                    f.write(f"{m.group(1)} {r['seconds']}\n")
            f.write("\n\n")
    script = (f"set terminal pngcairo size 640,420; set output '{os.path.join(OUT, 'mpi.png')}';"
              "set logscale x 2; set xlabel 'tile edge (pixels)'; set ylabel 'slowest rank / mean';"
              "set title 'Static interleaved tiles on the Cornell box: imbalance';"
              f"plot '{data}' index 0 with linespoints title '2 ranks', '' index 1 with linespoints title '4 ranks'")
    if shutil.which("gnuplot"):
        subprocess.run(["gnuplot", "-e", script], check=False)
    os.remove(data)


main()
