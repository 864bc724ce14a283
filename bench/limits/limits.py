#!/usr/bin/python3
"""The peer-and-limit table in one run: every solver and renderer against its peer and
against this machine's limit.

Runs the bench programs one after another on the same machine (so their
figures share one load), each writing its CSV to OUT/raw, then collates one
row per measure into OUT/limits.csv, OUT/limits.md (README's table) and
OUT/limits.png. Peers that are not installed (CGAL builds, Blender) leave
their rows marked "not run"; `scripts/bench --limits` installs them first.

The limits:
  stencil code (Poisson)  bytes its passes must stream, at the 2-thread triad
                          bandwidth of bench_stream (median);
  direct solvers          CHOLMOD alone on the same matrix, the best of its
                          orderings and of 1 or 2 BLAS threads;
  path tracer             Embree's own ray rate on the same scene and rays;
  rasteriser (Render)     llvmpipe's fill rate through the same OSMesa setup;
  particle code (MPM)     bytes per particle-substep at the triad bandwidth,
                          and the instruction rate.
"""
import argparse
import csv
import datetime
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]


def load1():
    return os.getloadavg()[0]


def read(raw, name):
    path = raw / f"{name}.csv"
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


# ---- the runs -------------------------------------------------------------------

def steps(quick):
    """(program, arguments): one run of each, in this order."""
    q = ["--quick"] if quick else []
    return [
        ("bench_stream", q),
        ("bench_poisson", ["--disk", "--size", "1024", "first"] + q),
        ("bench_parameterize", ["--generated", "--uniform"] + q),
        ("bench_arap", ["--generated"] + q),
        ("bench_pathtrace", ["embree", "rays", "lanes"] + q),
        ("bench_mpm", ["limit", "nbody"] + q),
        ("bench_shading", ["limits"] + q),
        ("bench_pathtrace", ["cycles"] + q),
        ("bench_cold", q),  # the same solvers as one `loom run` pays them (cold.md, after the table)
    ]


def run_all(build, out, quick, only):
    raw = out / "raw"
    logs = out / "logs"
    raw.mkdir(parents=True, exist_ok=True)
    logs.mkdir(parents=True, exist_ok=True)
    record = []
    todo = [s for s in steps(quick) if not only or s[0] in only]
    for i, (program, args) in enumerate(todo, 1):
        exe = build / "bin" / program
        label = f"{program} {' '.join(args)}".strip()
        if not exe.exists():
            print(f"[{i}/{len(todo)}] {label}: {exe} is not built: skipped", flush=True)
            record.append((label, "not built", 0.0, load1(), load1()))
            continue
        print(f"[{i}/{len(todo)}] {label} (load {load1():.2f}) ...", flush=True)
        before = load1()
        t0 = time.monotonic()
        log = logs / f"{program}-{'-'.join(a.strip('-') for a in args) or 'all'}.log"
        with open(log, "w") as f:
            rc = subprocess.call([str(exe), *args, "--out", str(raw)], stdout=f, stderr=subprocess.STDOUT)
        seconds = time.monotonic() - t0
        status = "ok" if rc == 0 else f"exit {rc} (see {log})"
        print(f"    {status}, {seconds:.0f} s", flush=True)
        record.append((label, status, seconds, before, load1()))
    with open(out / "runs.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["program", "status", "seconds", "load_before", "load_after"])
        w.writerows(record)


# ---- the collation ----------------------------------------------------------------

class Row:
    def __init__(self, measure, loom=float("nan"), peer_name="", peer=float("nan"), ratio=float("nan"),
                 target="", limit=float("nan"), limit_basis="", fraction=float("nan"), load=float("nan"),
                 note="", loom_text="", limit_text="", label=""):
        self.__dict__.update(locals())
        del self.__dict__["self"]


def triad(raw):
    rows = [r for r in read(raw, "stream") if r["kernel"] == "triad"]
    if not rows:
        return float("nan"), float("nan")
    top = max(int(r["threads"]) for r in rows)
    r = next(r for r in rows if int(r["threads"]) == top)
    return num(r["median_gb_per_s"]), num(r["best_gb_per_s"])


def poisson(raw, bandwidth):
    rows = read(raw, "poisson_disk")
    mg = [r for r in rows if r["solver"] == "multigrid" and abs(num(r["tolerance"]) - 2e-3) < 1e-9]
    cv = [r for r in rows if r["solver"] == "opencv"]
    if not mg or not cv:
        return [Row("Poisson blend, 1024² disk, multigrid to 2e-3", note="not run")]
    m = mg[0]
    n = int(m["size"])
    iterations = num(m["iterations"])
    # Traffic model (docs/poisson.md): per PCG iteration the fused V-cycle
    # sweeps, residual and transfers move ~250 B per cell and the CG updates
    # ~180 B (float×4 fields on the region's N×N grid); setup ~510 B per cell.
    model_bytes = (iterations * 430 + 510) * n * n
    limit = model_bytes / (bandwidth * 1e9)
    # The speed-up is of the medians of the same alternating rounds.
    ratio = num(m["speedup_vs_opencv"])
    loom = num(m["seconds"])
    return [Row(f"Poisson blend, {n}² disk, multigrid to 2e-3 (max error {num(m['max_error_255']):.3f}/255)",
                loom, "cv::seamlessClone", loom * ratio, ratio, "≥ 5×", limit,
                f"{model_bytes / 1e9:.1f} GB at the triad's {bandwidth:.1f} GB/s", limit / loom,
                num(m["load_average"]), label="Poisson 1024² disk: bandwidth")]


def direct_limit(rows, mesh, solves=1):
    """CHOLMOD's best analysis + factorization + `solves` solves over orderings and
    BLAS threads: (seconds, how), or (nan, "") when the rows are missing."""
    best = (float("nan"), "")
    keys = {(r["ordering"], r.get("blas_threads", "1")) for r in rows
            if r["mesh"] == mesh and r["part"].startswith("cholmod ") and r["ordering"] != "-"}
    for ordering, threads in keys:
        part = {r["part"]: num(r["seconds"]) for r in rows
                if r["mesh"] == mesh and (r["ordering"], r.get("blas_threads", "1")) == (ordering, threads)}
        analyze, factor, solve = part["cholmod analyze"], part["cholmod factor"], part["cholmod solve"]
        total = analyze + factor + solves * solve
        if not total >= best[0]:  # also replaces the first nan
            best = (total, f"CHOLMOD alone, {ordering}, {threads} BLAS thread{'s' if threads != '1' else ''}: "
                           f"analysis {analyze:.3f} + factorization {factor:.3f} + "
                           f"{solves if solves > 1 else ''}{' × ' if solves > 1 else ''}solve {solve:.3f} s")
    return best


def tutte(raw):
    rows = [r for r in read(raw, "parameterize") if r["boundary"] == "circle" and r["weights"] == "uniform"
            and r["mesh"] == "hemisphere_100k"]
    limit_rows = read(raw, "parameterize_limit")
    by = {r["impl"]: r for r in rows}
    if "loom" not in by:
        return [Row("Tutte, 100k-face hemisphere", note="not run")]
    loom = num(by["loom"]["seconds"])
    peer = by.get("cgal_sparselu")
    limit, basis = direct_limit(limit_rows, "hemisphere_100k")
    peer_s = num(peer["seconds"]) if peer else float("nan")
    return [Row("Tutte (uniform weights), 100k-face hemisphere, UVs to 1e-12 of CGAL's", loom,
                "CGAL 5.5 + Eigen SparseLU" if peer else "CGAL (not built)", peer_s, peer_s / loom, "≥ 10×",
                limit, basis, limit / loom, num(by["loom"]["load_average"]), label="Tutte 100k: CHOLMOD alone")]


def arap(raw):
    rows = read(raw, "arap")
    ours = [r for r in rows if r["method"] == "loom ARAP to its tolerance (alternating)"]
    cgal = [r for r in rows if r["method"] == "CGAL ARAP (alternating)"]
    if not ours or not cgal:
        return [Row("ARAP to its tolerance, 100k faces", note="not run (CGAL build needed)")]
    o, c = ours[-1], cgal[-1]
    iterations = int(num(o["iterations"]))
    loom, peer = num(o["seconds"]), num(c["seconds"])
    limit, basis = direct_limit(read(raw, "arap_limit"), o["mesh"], iterations)
    return [Row(f"ARAP to its tolerance, {o['mesh']} ({iterations} iterations, energy {num(o['energy']):.6f} "
                f"vs CGAL's {num(c['energy']):.6f})", loom, "CGAL ARAP_parameterizer_3", peer, peer / loom,
                "≥ 15×", limit, basis, limit / loom, label="ARAP 100k: CHOLMOD alone")]


def pathtrace(raw):
    out = []
    rows = read(raw, "pathtrace_embree")
    for threads in ("1", "2"):
        l = [r for r in rows if r["renderer"] == "loom" and r["threads"] == threads and r["size"] == "512"]
        e = [r for r in rows if r["renderer"] == "embree-pathtracer" and r["threads"] == threads and r["size"] == "512"]
        if not l or not e:
            continue
        lw, ew = num(l[0]["paths_per_s"]), num(e[0]["paths_per_s"])
        lc, ec = num(l[0]["paths_per_cpu_s"]), num(e[0]["paths_per_cpu_s"])
        out.append(Row(f"PathTrace paths/s, Cornell box 512², depth 8, {threads} thread{'s' if threads != '1' else ''}"
                       f" (per CPU second: {lc / ec:.2f}×)", 1 / lw, "Embree's tutorial path tracer", 1 / ew,
                       lw / ew, "≥ 1.0×", load=num(l[0]["load1"])))
    for r in read(raw, "pathtrace_rays"):
        # Written by `bench_pathtrace rays`: PathTrace's ray rate against
        # Embree's own on the same scene and rays.
        loom_rate, embree_rate = num(r["loom_rays_per_s"]), num(r["embree_rays_per_s"])
        scene = "Embree's Cornell box" if r.get("scene", "cornell") == "cornell" else \
            f"the Cornell box with a ball, {int(num(r['triangles'])):,} triangles"
        out.append(Row(f"PathTrace rays/s against Embree's ray rate, {scene}, {r['threads']} thread(s)", 1 / loom_rate,
                       limit=1 / embree_rate, limit_basis=f"Embree alone: {embree_rate / 1e6:.1f} M rays/s",
                       fraction=loom_rate / embree_rate, load=num(r["load1"]),
                       label=f"PathTrace {'box' if r.get('scene', 'cornell') == 'cornell' else 'box+ball'}, "
                             f"{r['threads']} thr.: Embree's rate"))
        tutorial_rate, embree_on_tutorial = num(r.get("tutorial_rays_per_s")), num(r.get("embree_on_tutorial_rays_per_s"))
        if tutorial_rate == tutorial_rate:  # not NaN: Embree's tutorial was installed
            # The peer's own fraction: Embree's tutorial path tracer against
            # Embree alone on the rays the tutorial casts.
            out.append(Row(f"Embree's tutorial path tracer rays/s against Embree's ray rate on its own rays, "
                           f"{scene}, {r['threads']} thread(s)", 1 / tutorial_rate, limit=1 / embree_on_tutorial,
                           limit_basis=f"Embree alone: {embree_on_tutorial / 1e6:.1f} M rays/s",
                           fraction=tutorial_rate / embree_on_tutorial, load=num(r["load1"]),
                           label=f"Embree's tutorial, {r['threads']} thr.: Embree's rate"))
    for r in read(raw, "pathtrace_lanes"):
        # Written by `bench_pathtrace lanes`: an experiment, not PathTrace (16
        # paths in SIMD lanes, 16-ray packets) against Embree alone on its packets.
        lanes_rate, packet_rate = num(r["lanes_rays_per_cpu_s"]), num(r["embree_packets_rays_per_cpu_s"])
        speedup = lanes_rate / num(r["pathtrace_rays_per_cpu_s"])
        out.append(Row(f"An experiment, not PathTrace: the box's estimator and samples with 16 paths in SIMD lanes "
                       f"and 16-ray packets, {r['threads']} thread(s), per CPU second "
                       f"({speedup:.2f}× PathTrace's rays; relMSE {num(r['lanes_relmse']):.4f}, "
                       f"PathTrace's {num(r['pathtrace_relmse']):.4f})", 1 / lanes_rate, limit=1 / packet_rate,
                       limit_basis=f"Embree alone on its packets: {packet_rate / 1e6:.1f} M rays/s",
                       fraction=lanes_rate / packet_rate, load=num(r["load1"]),
                       label=f"Lane experiment, {r['threads']} thr.: Embree packets"))
        # Its general variant: PathTrace's hit assembly and light sampler in
        # each lane, the same paths as PathTrace, against Embree alone on its packets.
        general_rate = num(r.get("general_rays_per_cpu_s"))
        if general_rate == general_rate:  # not NaN: a run that measured it
            general_packets = num(r["embree_general_packets_rays_per_cpu_s"])
            out.append(Row(f"An experiment, not PathTrace: the lane loop taking each hit and light sample from "
                           f"PathTrace's own code, {r['threads']} thread(s), per CPU second "
                           f"({general_rate / num(r['pathtrace_rays_per_cpu_s']):.2f}× PathTrace's rays; its image "
                           f"PathTrace's to relMSE {num(r['general_relmse_to_pathtrace_same_samples']):.1e})",
                           1 / general_rate, limit=1 / general_packets,
                           limit_basis=f"Embree alone on its packets: {general_packets / 1e6:.1f} M rays/s",
                           fraction=general_rate / general_packets, load=num(r["load1"]),
                           label=f"Lanes, PathTrace's parts, {r['threads']} thr."))
    for r in read(raw, "pathtrace_lanes_complete"):
        # Written by `bench_pathtrace lanes`: PathTrace's whole path loop 16
        # paths at a time (the scalar steps per lane, the Lambertian bounce in
        # SIMD), against PathTrace's own loop on the same samples.
        out.append(Row(f"An experiment, not PathTrace: PathTrace's whole path loop 16 paths at a time, {r['scene']}, "
                       f"{r['threads']} thread(s), rays per CPU second (every sample the same bits: {r['same_bits']})",
                       peer_name="PathTrace's loop, one path at a time",
                       ratio=num(r["lanes_over_pathtrace_loop"]), load=num(r["load1"])))
    ratios = read(raw, "pathtrace_cycles_ratios")
    for scene in sorted({r["scene"] for r in ratios}):
        vals = [num(r["time_ratio_at_equal_error"]) for r in ratios if r["scene"] == scene and r["renderer"] == "loom"]
        if vals:
            out.append(Row(f"PathTrace time to equal error vs Cycles, {scene}, 2 threads "
                           f"(range {min(vals):.2f}–{max(vals):.2f}× over Cycles' spp)",
                           peer_name="Blender 3.4 Cycles", ratio=statistics.median(vals), target="≥ 1.5×"))
    for r in read(raw, "pathtrace_cycles_references"):
        if r["what"].startswith("reference mean"):
            out.append(Row(f"PathTrace converged mean vs Cycles, {r['scene']}, {r['what'][len('reference mean, '):]}",
                           note=f"{num(r['difference_percent']):+.3f} %"))
    return out


def mpm(raw):
    """Written by `bench_mpm limit`: bytes per particle-substep at the triad measured beside it."""
    rows = read(raw, "mpm_limit")
    if not rows:
        return [Row("MPM particle-substeps", note="not run")]
    top = max(int(r["threads"]) for r in rows)
    out = []
    for r in rows:
        if int(r["threads"]) != top:
            continue
        bytes_per = num(r["bytes_per_particle_substep"])
        loom = 1 / (num(r["Mps_wall"]) * 1e6)
        limit = bytes_per / (num(r["triad_GB_per_s"]) * 1e9)
        loom_rate = num(r["Mps_wall"]) * 1e6
        out.append(Row(f"MPM {r['scene']}, {int(num(r['particles'])):,} particles, {top} threads: bandwidth", loom,
                       limit=limit, limit_basis=f"{bytes_per:.0f} B per particle-substep at the triad's "
                       f"{num(r['triad_GB_per_s']):.1f} GB/s (a loop streaming the same bytes: "
                       f"{1 / num(r['fraction_of_proxy']):.1f}× Loom's rate)",
                       fraction=num(r["fraction_of_triad"]), load=num(r["load"]),
                       loom_text=f"{loom_rate / 1e6:.1f} M/s", limit_text=f"{1e-6 / limit:.0f} M/s",
                       label=f"MPM {scene_name(r['scene'])}: bandwidth"))
        # The lower, binding limit (docs/mpm.md, "The limit"): instructions
        # per particle-substep, counted by callgrind (`bench_mpm count`,
        # load-independent), issued at Zen 4's 6 a cycle on every core at the
        # clock measured in this run.
        per_substep = next((n for prefix, n in INSTRUCTIONS.items() if r["scene"].startswith(prefix)), None)
        clock = [num(c["clock_ghz"]) for c in read(raw, "mpm_core_rate")]
        if per_substep and clock:
            rate = top * clock[0] * 1e9 * 6 / per_substep
            out.append(Row(f"MPM {r['scene']}: instruction issue", loom, limit=1 / rate,
                           limit_basis=f"{per_substep:,} instructions at 6 a cycle × {top} cores × {clock[0]:.2f} GHz",
                           fraction=loom_rate / rate, load=num(r["load"]),
                           loom_text=f"{loom_rate / 1e6:.1f} M/s", limit_text=f"{rate / 1e6:.0f} M/s",
                           label=f"MPM {scene_name(r['scene'])}: instruction issue"))
    return out


def scene_name(scene):
    """'2D fluid (mpm88) 512^2' -> '2D fluid'."""
    return " ".join(w for w in scene.split() if "^" not in w and not w.startswith("("))


# Instructions per particle-substep by scene, from callgrind (docs/mpm.md): the
# code as it runs now, with the transfers in SSE2 pairs (issue 39). The scalar
# code executed 680, 1037, 2121 and 3202; a limit from those counts would no
# longer be a limit (the same work now takes fewer instructions), so the table
# uses the new ones and docs/mpm.md gives the fraction against both.
INSTRUCTIONS = {"2D fluid": 626, "2D elastic": 984, "3D fluid": 1717, "3D elastic": 2804}


def shading(raw):
    """Written by `bench_shading limits`: the Render frame against llvmpipe's rates, alternated."""
    rows = read(raw, "shading_limits")
    frame = [r for r in rows if r["measure"].startswith("Render frame")]
    if not frame:
        return [Row("Render 1920×1080, 100k triangles, 2048² shadow map, 5×5 PCF, 4× MSAA", note="not run")]
    out = []
    for r in rows:
        if r["measure"].startswith("limit:"):
            what = r["measure"][len("limit: "):].split(" / ")
            out.append(Row(f"Render 1080p, 100k triangles, 2048² map, 5×5 PCF, 4× MSAA ({what[1]})",
                           num(r["seconds"]) / num(r["fraction_of_limit"]), limit=num(r["seconds"]),
                           limit_basis=f"llvmpipe, {r['lp_threads'].split(' ')[0]} threads: {what[0]}",
                           fraction=num(r["fraction_of_limit"]), load=num(r["load1"]),
                           label=f"Render {what[1].replace('Render ', '')}: {what[0].split(' (')[0]}"))
    return out


def stages(raw):
    """Where the direct solvers' time goes: each stage's median wall time, from the same run."""
    lines = []
    for name, csv_name in (("Tutte", "parameterize_limit"), ("ARAP", "arap_limit")):
        rows = [r for r in read(raw, csv_name) if r["ordering"] == "-"]
        if rows:
            lines.append("")
            lines.append(f"{name}, {rows[0]['mesh']}: " +
                         ", ".join(f"{r['part']} {num(r['seconds']):.3f} s" for r in rows) + ".")
    return lines


def collate(out):
    raw = out / "raw"
    bandwidth, best = triad(raw)
    rows = [Row("STREAM triad, 2 threads (median of runs; best %.1f GB/s)" % best, note=f"{bandwidth:.1f} GB/s")]
    rows += poisson(raw, bandwidth) + tutte(raw) + arap(raw) + pathtrace(raw) + mpm(raw) + shading(raw)
    fields = ["measure", "loom", "peer_name", "peer", "ratio", "target", "limit", "limit_basis", "fraction", "load",
              "note"]
    with open(out / "limits.csv.tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields)
        for r in rows:
            w.writerow([getattr(r, k) for k in fields])
    os.replace(out / "limits.csv.tmp", out / "limits.csv")

    def fmt(x, unit=""):
        return "" if x != x else (f"{x:.3g}{unit}")

    lines = ["| measure | Loom | peer | ratio | target | limit here | fraction of the limit |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        peer = f"{r.peer_name} {fmt(r.peer, ' s')}".strip()
        loom = r.loom_text or fmt(r.loom, " s") or r.note
        limit = r.limit_text or fmt(r.limit, " s")
        lines.append(f"| {r.measure} | {loom} | {peer} | {('**' + fmt(r.ratio, '×') + '**') if r.ratio == r.ratio else ''}"
                     f" | {r.target} | {(limit + ': ' + r.limit_basis) if r.limit_basis else ''}"
                     f" | {('**' + f'{r.fraction:.2f}' + '**') if r.fraction == r.fraction else ''} |")
    lines += stages(raw)
    if (raw / "cold.md").exists():
        lines += ["", "Cold and warm, the same solvers in one `loom run` (bench_cold):", "",
                  (raw / "cold.md").read_text().rstrip()]
    runs = out / "runs.csv"
    if runs.exists():
        with open(runs) as f:
            loads = [num(x["load_before"]) for x in csv.DictReader(f)]
        lines.append("")
        lines.append(f"One run, {datetime.date.today()}: load {min(loads):.2f}–{max(loads):.2f} at the start of "
                     f"each program ({runs}).")
    (out / "limits.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    plot(out, rows)


def plot(out, rows):
    """Horizontal bars: each measure's fraction of its limit."""
    if not shutil.which("gnuplot"):
        print("gnuplot is not installed: no plot")
        return
    data = [((r.label or r.measure.split(" (")[0])[:60].replace('"', "'"), r.fraction)
            for r in rows if r.fraction == r.fraction]
    if not data:
        return
    dat = out / "limits.dat"
    dat.write_text("".join(f'"{name}" {fraction:.4f}\n' for name, fraction in reversed(data)))
    script = f"""set terminal pngcairo size 1000,{160 + 30 * len(data)} noenhanced
set output '{out / "limits.png"}'
set title "Fraction of this machine's limit (1 = at the limit; dashed: half)"
set style fill solid 0.6
set xrange [0:1.1]
set yrange [-0.6:{len(data) - 0.4}]
set grid xtics
set lmargin 44
set arrow from 0.5, graph 0 to 0.5, graph 1 nohead dt 2
plot '{dat}' using ($2/2):0:($2/2):(0.35):yticlabels(1) with boxxyerror notitle, \\
     '' using 2:0:(sprintf("%.2f", $2)) with labels left offset 0.5,0 notitle
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=False)
    dat.unlink()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=str(SOURCE / "build"), help="the build folder (default: build)")
    p.add_argument("--out", default=str(SOURCE / "bench" / "results" / "limits"),
                   help="where raw CSVs, logs and the table go (default: bench/results/limits)")
    p.add_argument("--quick", action="store_true", help="pass --quick to every program (a smoke run)")
    p.add_argument("--collate-only", action="store_true", help="only rebuild the table from OUT/raw")
    p.add_argument("programs", nargs="*", help="run only these programs (e.g. bench_poisson)")
    a = p.parse_args()
    out = Path(a.out)
    if not a.collate_only:
        run_all(Path(a.build), out, a.quick, set(a.programs))
    collate(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
