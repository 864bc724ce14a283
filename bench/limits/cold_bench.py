#!/usr/bin/python3
"""bench_cold: what one `loom run` pays that a warm loop does not (issue 39, item 7).

The limits table (docs/limits.md) times each solver in a warm loop of a
benchmark program: the kernel alone, repeated in one process. A user runs
one `loom run`. For Poisson 1024² (a disk), Tutte and ARAP on a 100k-face
hemisphere (the table's inputs), PathTrace on the Cornell box, MPM's 2D
fluid and Render's frame (the table's scenes), this measures, medians of --runs:

  warm node  the node's seconds in a loom.Session that has run the graph
             before (its cache cleared between runs): a warm process;
  cold node  the node's seconds in one `loom run --profile` (a fresh process);
  run wall   that `loom run`'s whole wall time (process start, plugins, inputs,
             outputs); both also with malloc's memory on 4-KiB pages, as
             before decision 29 (GLIBC_TUNABLES=glibc.malloc.hugetlb=0);
  peer       OpenCV's seamlessClone on the same files, its first call in a
             fresh process (cold) and its later calls (warm).

ARAP is run as a user runs it (its defaults: an ASAP start) and as the limits
table's row runs it (a Tutte start). Writes cold.csv and cold.md (the table
of docs/limits.md's "Cold and warm" section) and cold.png to --out.
"""
import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def poisson_graph(inputs):
    load = lambda name: {"type": "LoadImage", "inputs": {"path": str(inputs / name), "decode": "keep"}}
    return {"loom": 1, "nodes": {
        "source": load("source-1024.png"), "target": load("target-1024.png"), "mask": load("mask-1024.png"),
        "blend": {"type": "PoissonBlend", "inputs": {
            "source": {"from": "source.image"}, "target": {"from": "target.image"},
            "mask": {"from": "mask.image"}, "offset": [31, 31], "tolerance": 0.002}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "blend.image"}, "path": "blend.png"}}}}


def mesh_graph(inputs, solver):
    return {"loom": 1, "nodes": {
        "dome": {"type": "LoadMesh", "inputs": {"path": str(inputs / "hemisphere-99k.obj")}},
        "solve": solver,
        "save": {"type": "SaveMesh", "inputs": {"mesh": {"from": "solve.mesh"}, "path": "out.obj"}}}}


def pathtrace_graph(_inputs):
    """The Cornell box with its blocks, 512², depth 8 (the limits table's
    PathTrace rows), 16 samples per pixel."""
    return {"loom": 1, "nodes": {
        "box": {"type": "CornellBox", "inputs": {"contents": "blocks"}},
        "trace": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}, "size": [512, 512], "spp": 16,
                                                  "max_depth": 8}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "trace.image"}, "path": "trace.exr"}}}}


def mpm_graph(_inputs):
    """The limits table's 2D fluid: mpm88 scaled to 1M particles on 512², the
    bench's substep of 2e-5 s; one frame of 10 substeps."""
    return {"loom": 1, "time": {"start": 1, "end": 2, "fps": 5000}, "nodes": {
        "water": {"type": "MPMEmitBox", "inputs": {
            "dimension": 2, "min": [0.2, 0.2, 0], "max": [0.6, 0.6, 0], "material": "fluid", "E": 400.0,
            "density": 1.0, "sampling": "random", "count": 1000000, "particle_volume": 0.16 / 1000000}},
        "sim": {"type": "MPMStep", "inputs": {"state": {"from": "water.particles"}, "resolution": 512,
                                             "gravity": [0, -9.8, 0], "walls": "separate", "wall_cells": 3,
                                             "cfl": 1.0, "dt_max": 2e-5}},
        "image": {"type": "MPMSplat", "inputs": {"state": {"from": "sim.state"}, "width": 256}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "image.image"}, "path": "mpm_{frame}.png"}}}}


def render_graph(_inputs):
    """The limits table's Render frame (bench_shading's target): a sphere of
    about 100k triangles over an 8 m floor, one shadowed sun, 1080p, 4× MSAA,
    a 2048² shadow map with 5×5 PCF; the image alone."""
    return {"loom": 1, "nodes": {
        "floor_mesh": {"type": "GridMesh", "inputs": {"size": [8, 8], "resolution": [1, 1],
                                                      "rotate_degrees": [-90, 0, 0]}},
        "gray": {"type": "Material", "inputs": {"base_color": [0.8, 0.8, 0.8], "specular": 0}},
        "floor": {"type": "Object", "inputs": {"mesh": {"from": "floor_mesh.mesh"}, "material": {"from": "gray.material"}}},
        "ball_mesh": {"type": "UVSphere", "inputs": {"radius": 1, "rings": 158, "segments": 316}},
        "red": {"type": "Material", "inputs": {"base_color": [0.8, 0.4, 0.3], "specular": 0.5}},
        "ball": {"type": "Object", "inputs": {"mesh": {"from": "ball_mesh.mesh"}, "material": {"from": "red.material"},
                                              "translate": [0, 1.2, 0]}},
        "sun": {"type": "Light", "inputs": {"kind": "directional", "direction": [-0.5, -1, -0.4], "intensity": 3}},
        "camera": {"type": "Camera", "inputs": {"eye": [0, 3, 6], "target": [0, 0.8, 0], "fov_degrees": 45.84}},
        "sky": {"type": "Environment", "inputs": {"color": [0.1, 0.1, 0.1]}},
        "scene": {"type": "MergeScenes", "inputs": {"a": {"from": "floor.scene"}, "b": {"from": "ball.scene"},
                                                    "c": {"from": "sun.scene"}, "d": {"from": "camera.scene"},
                                                    "e": {"from": "sky.scene"}}},
        "render": {"type": "Render", "inputs": {"scene": {"from": "scene.scene"}, "width": 1920, "height": 1080,
                                                "samples": 4, "shadows": "pcf", "pcf_size": 5,
                                                "shadow_resolution": 2048, "extra_images": False}},
        "save": {"type": "SaveImage", "inputs": {"image": {"from": "render.image"}, "path": "render.exr"}}}}


def mesh_measure(solver):
    return lambda inputs: mesh_graph(inputs, solver)


# (what, the measured node, its graph from the inputs' folder, whether OpenCV's seamlessClone is its peer)
MEASURES = [
    ("Poisson blend, 1024² disk, multigrid to 2e-3", "blend", poisson_graph, True),
    ("Tutte (uniform weights), hemisphere-99k", "solve",
     mesh_measure({"type": "Parameterize", "inputs": {"mesh": {"from": "dome.mesh"}, "weights": "uniform"}}), False),
    ("ARAP, hemisphere-99k, Tutte start (the limits table's)", "solve",
     mesh_measure({"type": "ARAP", "inputs": {"mesh": {"from": "dome.mesh"}, "init": "tutte"}}), False),
    ("ARAP, hemisphere-99k, defaults (ASAP start)", "solve",
     mesh_measure({"type": "ARAP", "inputs": {"mesh": {"from": "dome.mesh"}}}), False),
    ("PathTrace, Cornell box 512², depth 8, 16 spp", "trace", pathtrace_graph, False),
    ("MPM 2D fluid, 1M particles, 512², 10 substeps", "sim", mpm_graph, False),
    ("Render 1080p, 100k triangles, 2048² map, 5×5 PCF, 4× MSAA", "render", render_graph, False),
]


def cold_run(loom, graph, work, small_pages=False):
    """One `loom run --profile`: (the node seconds by id, the command's wall).
    small_pages: as before decision 29, malloc's memory on 4-KiB pages."""
    profile = work / "profile.json"
    env = {**os.environ, "GLIBC_TUNABLES": "glibc.malloc.hugetlb=0"} if small_pages else None
    start = time.perf_counter()
    done = subprocess.run([loom, "run", str(graph), "--out", str(work / "out"), "--no-cache", "-q",
                           "--profile", str(profile)], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"bench_cold: loom run {graph} failed:\n{done.stderr}")
    nodes = json.loads(profile.read_text())["nodes"]
    return {id: n["seconds"] for id, n in nodes.items()}, wall


def warm_runs(graph, node, runs, work):
    """The node's seconds in one Session, after a first run (not counted)."""
    import loom
    session = loom.Session(disk_cache=False, output_dir=str(work / "out"))
    g = loom.load(str(graph))
    seconds = []
    for k in range(runs + 1):
        session.clear_cache()
        result = session.run(g)
        if k > 0:
            seconds.append(result.nodes[node]["seconds"])
    return seconds


def opencv_peer(peer, inputs, runs):
    """seamlessClone's first call in each of `runs` processes, and its later calls."""
    # Placed as bench_poisson places it: the centre of the disk's bounding box
    # (columns and rows 1 .. 1023 of the source), moved by the offset (31, 31).
    first, later = [], []
    for _ in range(runs):
        out = subprocess.run([peer, str(inputs / "source-1024.png"), str(inputs / "target-1024.png"),
                              str(inputs / "mask-1024.png"), "542", "542", "4"], capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"bench_cold: {peer} failed:\n{out.stderr}")
        calls = [float(x) for x in out.stdout.split()]
        first.append(calls[0])
        later += calls[1:]
    return statistics.median(first), statistics.median(later)


def bench_kernels(bin_dir, inputs, raw, quick):
    """The limits table's warm loops on the same inputs, which they write:
    bench_poisson's multigrid to 2e-3 and OpenCV (seconds), and the meshes."""
    q = ["--quick"] if quick else []
    env = {**os.environ, "LOOM_BENCH_OUT": str(raw)}
    subprocess.run([str(bin_dir / "bench_poisson"), "--disk", "--size", "1024", "first", "--write-inputs", str(inputs),
                    "--out", str(raw)] + q, check=True, capture_output=True, env=env)
    subprocess.run([str(bin_dir / "bench_arap"), "--write-meshes", str(inputs)], check=True, capture_output=True)
    with open(raw / "poisson_disk.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    pick = lambda solver, tol: next(float(r["seconds"]) for r in rows
                                    if r["solver"].strip() == solver and abs(float(r["tolerance"]) - tol) < 1e-12)
    return pick("multigrid", 0.002), pick("opencv", 0)


def plot(out, rows):
    """Clustered bars per measure: the kernel's warm loop, the node warm, the
    node cold, and the node cold on 4-KiB pages (cold.png)."""
    if not shutil.which("gnuplot"):
        print("gnuplot is not installed: no plot")
        return
    dat = out / "cold.dat"
    value = lambda v: f"{v:.4f}" if isinstance(v, float) else "NaN"
    label = lambda m: m.split(",")[0].split(" (")[0] + ("" if "ARAP" not in m else
                                                       " (" + m.split(", ")[-1].split(" (")[0] + ")")
    dat.write_text("".join(f'"{label(r["measure"])}" '
                           f'{value(r["kernel_warm_loop_s"])} {value(r["warm_node_s"])} {value(r["cold_node_s"])} '
                           f'{value(r["cold_node_small_pages_s"])}\n' for r in rows))
    script = f"""set terminal pngcairo size 1100,520 noenhanced
set output '{out / "cold.png"}'
set title "Seconds of the solver: warm loop, warm node, one loom run (medians)"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.7
set ylabel "seconds"
set grid ytics
set key top left
plot '{dat}' using 2:xtic(1) title "kernel, the bench's warm loop", '' using 3 title "node, warm Session", \
     '' using 4 title "node, one loom run", '' using 5 title "node, one loom run on 4-KiB pages (decision 29 off)"
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=False)
    dat.unlink()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("loom", help="the loom program")
    p.add_argument("--peer", help="poisson_opencv_peer (default: beside loom)")
    p.add_argument("--runs", type=int, default=5, help="runs of each (medians; default 5)")
    p.add_argument("--quick", action="store_true", help="one run of each")
    p.add_argument("--only", help="only the measures whose name contains this text (e.g. Render)")
    p.add_argument("--out", help="folder for cold.csv and cold.md (default: $LOOM_BENCH_OUT, else bench/results)")
    args = p.parse_args()
    if args.quick:
        args.runs = 1
    loom = os.path.abspath(args.loom)
    peer = args.peer or str(Path(loom).parent / "poisson_opencv_peer")
    out = Path(args.out or os.environ.get("LOOM_BENCH_OUT") or Path(__file__).resolve().parents[2] / "bench" / "results")
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="loom-cold-") as tmp:
        work = Path(tmp)
        inputs, raw = work / "inputs", work / "raw"
        inputs.mkdir()
        raw.mkdir()
        load_start = os.getloadavg()[0]
        kernel, opencv_warm_loop = bench_kernels(Path(loom).parent, inputs, raw, args.quick)
        for k, (name, node, make_graph, has_peer) in enumerate(MEASURES):
            if args.only and args.only not in name:
                continue
            graph = work / f"measure{k}.json"
            graph.write_text(json.dumps(make_graph(inputs)))
            cold, small, walls, small_walls, warm = [], [], [], [], []
            for _ in range(args.runs):  # alternated, so that load falls on each
                seconds, wall = cold_run(loom, graph, work)
                cold.append(seconds[node])
                walls.append(wall)
                seconds, wall = cold_run(loom, graph, work, small_pages=True)
                small.append(seconds[node])
                small_walls.append(wall)
                warm += warm_runs(graph, node, 1, work)
            row = {"measure": name, "kernel_warm_loop_s": "", "warm_node_s": statistics.median(warm),
                   "cold_node_s": statistics.median(cold), "run_wall_s": statistics.median(walls),
                   "cold_node_small_pages_s": statistics.median(small),
                   "run_wall_small_pages_s": statistics.median(small_walls), "peer": "",
                   "peer_warm_loop_s": "", "peer_cold_s": "", "peer_warm_s": ""}
            if has_peer:
                row["kernel_warm_loop_s"], row["peer_warm_loop_s"] = kernel, opencv_warm_loop
                row["peer"] = "OpenCV seamlessClone"
                row["peer_cold_s"], row["peer_warm_s"] = opencv_peer(peer, inputs, args.runs)
            rows.append(row)
            print(f"{name}: warm {row['warm_node_s']:.3f} s, cold {row['cold_node_s']:.3f} s, "
                  f"loom run {row['run_wall_s']:.3f} s", flush=True)
        load_end = os.getloadavg()[0]
    with open(out / "cold.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]) + ["load_average"])
        w.writeheader()
        for r in rows:
            w.writerow({**r, "load_average": f"{load_start:.2f}-{load_end:.2f}"})
    fmt = lambda v: f"{v:.3f} s" if isinstance(v, float) else ""
    lines = ["| measure | kernel, the bench's warm loop | node, warm (a Session's later runs) | node, cold (one "
             "`loom run`) | cold / warm node | `loom run` wall | the same two on 4-KiB pages (before decision 29) | "
             "peer: warm loop / first call in a process / later calls | ratio, warm loops / cold (node against "
             "the peer's first call) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        peer_text = ratio = ""
        if r["peer"]:
            peer_text = f"{r['peer']} {fmt(r['peer_warm_loop_s'])} / {fmt(r['peer_cold_s'])} / {fmt(r['peer_warm_s'])}"
            ratio = (f"{r['peer_warm_loop_s'] / r['kernel_warm_loop_s']:.2f}× / "
                     f"{r['peer_cold_s'] / r['cold_node_s']:.2f}×")
        lines.append(f"| {r['measure']} | {fmt(r['kernel_warm_loop_s'])} | {fmt(r['warm_node_s'])} | "
                     f"{fmt(r['cold_node_s'])} | {r['cold_node_s'] / r['warm_node_s']:.2f}× | {fmt(r['run_wall_s'])} | "
                     f"{fmt(r['cold_node_small_pages_s'])} / {fmt(r['run_wall_small_pages_s'])} | {peer_text} | {ratio} |")
    lines.append(f"\nMedians of {args.runs}; load average {load_start:.2f} at the start, {load_end:.2f} at the end.")
    (out / "cold.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    plot(out, rows)


if __name__ == "__main__":
    main()
