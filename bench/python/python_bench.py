"""bench_python: what `import loom` costs on top of the engine.

  overhead   session.run on a fully cached graph (chains of 1, 10, 100 Math nodes)
  image4k    a cached 3840x2160 RGB image into NumPy (a view), against copying it;
             and a 3840x2160 NumPy image given to a node input (copied and hashed once)
  pynode     a Python node's call against an equivalent C++ node: chains of N
             Add (Python) / Math (C++) nodes, cache cleared before every run

Writes python.csv and python.png to --out (else $LOOM_BENCH_OUT, else
bench/results). Minimum and median of the repeats, with the machine load (printed)."""

import argparse
import csv
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def seconds(fn, repeats):
    """(minimum, median) over repeats: the minimum is the cost without
    interference from other work, the median what a user sees on this machine."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times)


def add_rows(rows, part, measure, n, pair, scale, unit):
    rows.append((part, measure + " (min)", n, pair[0] * scale, unit))
    rows.append((part, measure + " (median)", n, pair[1] * scale, unit))


def math_chain(loom, n, python):
    g = loom.Graph()
    prev = None
    for k in range(n):
        a = prev if prev is not None else 0.0
        node = g.add("py.bench_nodes.Add", a=a, b=1.0) if python else g.add("Math", a=a, b=1.0, op="add")
        prev = node.result
    return g, prev


def bench_overhead(loom, session, rows, repeats):
    for n in (1, 10, 100):
        g, out = math_chain(loom, n, python=False)
        session.run(g, out)  # fill the cache
        add_rows(rows, "overhead", f"cached run, {n} nodes", n, seconds(lambda: session.run(g, out), repeats),
                 1e6, "us per run")


def bench_image4k(loom, session, rows, repeats):
    g = loom.Graph()
    board = g.add("Checkerboard", size=[3840, 2160], cells=27)
    img = session.run(g, board.image)
    add_rows(rows, "image4k", "cached 3840x2160x3 run to NumPy view", 1,
             seconds(lambda: session.run(g, board.image), repeats), 1e3, "ms")
    add_rows(rows, "image4k", "np.array copy of the same (reference)", 1, seconds(lambda: np.array(img), repeats),
             1e3, "ms")
    a = np.random.default_rng(1).random((2160, 3840, 3), dtype=np.float32)
    add_rows(rows, "image4k", "3840x2160x3 NumPy image given to an input (copy + hash)", 1,
             seconds(lambda: loom.Graph().add("Switch", in0=a), max(3, repeats // 10)), 1e3, "ms")


def bench_pynode(loom, rows, repeats, threads, n):
    # The two chains alternate, so that load from elsewhere falls on both; the
    # minimum over repeats is the cost without interference.
    session = loom.Session(threads=threads, disk_cache=False)
    chains = {python: math_chain(loom, n, python) for python in (False, True)}
    for g, out in chains.values():
        assert session.run(g, out) == float(n)
    times = {False: [], True: []}
    for _ in range(repeats):
        for python, (g, out) in chains.items():
            session.clear_cache()
            start = time.perf_counter()
            session.run(g, out)
            times[python].append((time.perf_counter() - start) / n)
    best = {python: min(t) for python, t in times.items()}
    for python in (False, True):
        name = "Python Add" if python else "C++ Math"
        rows.append(("pynode", f"{name} node, chain of {n}, cold (min)", n, best[python] * 1e6, "us per node"))
        rows.append(("pynode", f"{name} node, chain of {n}, cold (median)", n,
                     statistics.median(times[python]) * 1e6, "us per node"))
    rows.append(("pynode", "Python node call overhead over C++ (min)", n, (best[True] - best[False]) * 1e6,
                 "us per node"))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for ax, part in zip(axes, ("overhead", "image4k", "pynode")):
        mine = [r for r in rows if r[0] == part]
        ax.barh([r[1] for r in mine], [r[3] for r in mine])
        ax.set_xlabel(mine[0][4] if len(set(r[4] for r in mine)) == 1 else mine[-1][4])
        ax.set_title(part)
        ax.tick_params(axis="y", labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("parts", nargs="*", help="overhead, image4k, pynode (default: all)")
    p.add_argument("--quick", action="store_true", help="fewer repeats")
    p.add_argument("--out", default=os.environ.get("LOOM_BENCH_OUT") or os.path.join(HERE, "..", "results"))
    p.add_argument("--threads", type=int, default=1, help="engine threads for the node chains")
    args = p.parse_args()
    parts = args.parts or ["overhead", "image4k", "pynode"]
    for part in parts:
        if part not in ("overhead", "image4k", "pynode"):
            p.error(f"unknown part {part!r}: overhead, image4k or pynode")
    repeats = 20 if args.quick else 100

    os.environ["LOOM_PYTHON_PATH"] = HERE + ":" + os.environ.get("LOOM_PYTHON_PATH", "")
    sys.path.insert(0, HERE)
    import loom
    session = loom.Session(threads=args.threads, disk_cache=False)
    rows = []
    if "overhead" in parts:
        bench_overhead(loom, session, rows, repeats * 5)
    if "image4k" in parts:
        bench_image4k(loom, session, rows, repeats)
    if "pynode" in parts:
        bench_pynode(loom, rows, max(10, repeats // 2), args.threads, 200)

    os.makedirs(args.out, exist_ok=True)
    load = os.getloadavg()
    with open(os.path.join(args.out, "python.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["part", "measure", "nodes", "value", "unit", "load1"])
        for r in rows:
            w.writerow([*r[:3], f"{r[3]:.3f}", r[4], f"{load[0]:.1f}"])
    for r in rows:
        print(f"{r[0]:9} {r[1]:58} {r[3]:10.3f} {r[4]}")
    print(f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}; wrote {os.path.join(args.out, 'python.csv')}")
    if len(parts) == 3:
        plot(rows, os.path.join(args.out, "python.png"))


if __name__ == "__main__":
    main()
