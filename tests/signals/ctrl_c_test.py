"""Ctrl-C within half a second, everywhere (issue 37): for each long-running
node and driver, `loom run` on a generated graph that runs for many seconds,
SIGINT about 1 s into the work (for the solvers: after a given amount of CPU
time, so the signal lands in the same step whatever the load), then:

- the process exits within BOUND = 0.5 s x LOAD of the signal (the measured
  figure is printed). LOAD = max(1, 1-minute load average / cores), at most 6,
  so a shared CI machine gets more time; LOOM_CTRLC_LOAD overrides it.
  Before the fix each case but "--watch, waiting" (a control, fine before)
  took 5.0-5.4 s: the runner's 5-s watchdog ended it. The runner now leaves
  0.3 s after the signal whatever its nodes do (for calls that cannot stop,
  such as a sparse factorization); every case but ARAP's sets that grace to
  30 s, so what is measured is the node stopping at its own checks;
- the exit code is 130 and the last line says "interrupted" (a run that ended
  before the signal is a failure: the graph is too small);
- --out holds no file but those a case lists as whole (a sweep's finished
  points) and no staging file.

Usage: ctrl_c_test.py LOOM SOURCE_DIR [unittest arguments]."""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

LOOM, SOURCE = map(os.path.abspath, sys.argv[1:3])
del sys.argv[1:3]

QUIET_BOUND = 0.5  # seconds from SIGINT to exit, on a quiet machine
# The runner leaves 0.3 s after a signal whatever its nodes do (the grace,
# for calls that cannot stop): a case that checks a node stops at its own
# checks runs with a grace far longer than any bound, so the grace cannot
# hide a node that never checks.
COOPERATIVE_GRACE = "30"
PYTHON_PLUGIN = os.path.exists(os.path.join(os.path.dirname(os.path.dirname(LOOM)), "lib", "loom", "plugins",
                                            "libloom_python.so"))


def load_factor():
    if "LOOM_CTRLC_LOAD" in os.environ:
        return float(os.environ["LOOM_CTRLC_LOAD"])
    return min(6.0, max(1.0, os.getloadavg()[0] / (os.cpu_count() or 1)))


def write_json(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def cpu_seconds(pid):
    """User and system CPU time of a process (all its threads)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def catches_sigint(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            caught = [l for l in f.read().splitlines() if l.startswith("SigCgt:")]
    except OSError:
        return False
    return bool(caught) and bool(int(caught[0].split()[1], 16) & (1 << (signal.SIGINT - 1)))


class Run:
    """`loom run ARGS` with its stderr read line by line as it comes."""

    def __init__(self, args, env=None, cwd=None, grace=COOPERATIVE_GRACE):
        self.lines = []
        self.changed = threading.Condition()
        environment = dict(os.environ, **(env or {}))
        environment.pop("LOOM_STOP_GRACE", None)
        if grace is not None:
            environment["LOOM_STOP_GRACE"] = grace
        self.proc = subprocess.Popen([LOOM, "run", *map(str, args)], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True, cwd=cwd, env=environment)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.proc.stderr:
            with self.changed:
                self.lines.append(line.rstrip("\n"))
                self.changed.notify_all()
        with self.changed:
            self.changed.notify_all()

    def wait_for_line(self, start, timeout=60):
        """Until a stderr line starting with `start` (or the process ends)."""
        deadline = time.time() + timeout
        with self.changed:
            while not any(l.startswith(start) for l in self.lines):
                if self.proc.poll() is not None or time.time() > deadline:
                    return False
                self.changed.wait(0.05)
        return True

    def wait_for_handler(self, timeout=60):
        deadline = time.time() + timeout
        while not catches_sigint(self.proc.pid) and time.time() < deadline and self.proc.poll() is None:
            time.sleep(0.01)

    def interrupt(self):
        """SIGINT; returns the seconds until the process exits."""
        sent = time.monotonic()
        self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        seconds = time.monotonic() - sent
        self.reader.join(timeout=5)
        return seconds

    def stderr(self):
        return "\n".join(self.lines)


class CtrlCTest(unittest.TestCase):
    figures = []

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-ctrlc-")
        self.out = os.path.join(self.dir, "out")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def graph(self, nodes, **extra):
        return write_json(os.path.join(self.dir, "g.json"), {"loom": 1, "seed": 1, "nodes": nodes, **extra})

    def interrupt(self, name, run, after=None, delay=1.0, cpu=None, whole=lambda path: False, quiet_bound=QUIET_BOUND):
        """Waits until the node `after` is done (else until the handlers are
        installed), then `delay` more seconds, or with `cpu` until the process
        has used that many more CPU seconds (a point inside one step of the
        node, however loaded the machine), then SIGINT; checks the bound, exit
        code, message and --out. `whole(path)` says which files may stay."""
        run.wait_for_handler()
        if after:  # a node's "done" line, or any line starting so ("[s] wrote")
            self.assertTrue(run.wait_for_line(after if after.startswith("[") else f"[{after}] done"), run.stderr())
        if cpu is None:
            time.sleep(delay)
        else:
            start, deadline = cpu_seconds(run.proc.pid), time.time() + 120
            while run.proc.poll() is None and cpu_seconds(run.proc.pid) - start < cpu and time.time() < deadline:
                time.sleep(0.01)
        self.assertIsNone(run.proc.poll(), f"{name}: ended before the signal (too small):\n{run.stderr()}")
        seconds = run.interrupt()
        bound = quiet_bound * load_factor()
        if any("leaving without them" in line for line in run.lines):
            name += " (the grace)"
        self.figures.append((name, seconds, bound))
        print(f"\n{name}: SIGINT -> exit {seconds:.2f} s (bound {bound:.2f} s)", file=sys.stderr)
        self.assertEqual(run.proc.returncode, 130, run.stderr())
        self.assertIn("interrupted by SIGINT", run.stderr())
        self.assertNotIn("failed: cancelled", run.stderr())  # a stopped node is cancelled, not failed
        left = []
        for folder, _, files in os.walk(self.out):
            for f in files:
                path = os.path.join(folder, f)
                if ".loomtmp" in f or not whole(path):
                    left.append(os.path.relpath(path, self.out))
        self.assertEqual(left, [], "files left in --out")
        self.assertLessEqual(seconds, bound, f"{name}: {seconds:.2f} s from SIGINT to exit\n{run.stderr()}")

    def run_graph(self, nodes, *args, env=None, grace=COOPERATIVE_GRACE, **extra):
        return Run([self.graph(nodes, **extra), "--out", self.out, "--no-cache", *args], env=env, grace=grace)

    # ARAP at 90,000 vertices: the system's assembly and factorization, the
    # ASAP start, then iterations. CHOLMOD's factorizations cannot be
    # interrupted (the ASAP start's takes 0.6-1.3 s here, at 640,000 vertices
    # 1.9 s for the smaller one), so this case runs with the runner's own
    # grace: the signal lands in an assembly (the node stops at its check) or
    # in a factorization (the runner leaves after 0.3 s, staging files
    # removed); either way within the bound. CI once measured 0.72 s here,
    # with the grace at 5 s.
    def test_arap(self):
        run = self.run_graph({
            "g": {"type": "GridMesh", "inputs": {"resolution": [299, 299]}},
            "a": {"type": "ARAP", "inputs": {"mesh": {"from": "g.mesh"}, "iterations": 10000, "tolerance": 0}},
            "s": {"type": "SaveMesh", "inputs": {"mesh": {"from": "a.mesh"}, "path": "a.obj"}}}, grace=None)
        self.interrupt("ARAP 90k vertices", run, cpu=1.0)

    # Cloth by Newton's method at 150 x 150 vertices: Hessian assembly,
    # factorization and line search per iteration. The assembly and the line
    # search check; CHOLMOD's analysis and factorization cannot be
    # interrupted, and a signal that lands in them waits for them. Since the
    # assembly became a refill in place (2026-11-29) it is a small part of an
    # iteration, so at 300 x 300 (270,000 unknowns) the signal mostly landed
    # in a factorization and waited up to 1.8 s (load 5, over a bound of 1.76
    # s); at 67,500 unknowns SIGINT to exit took 0.08-1.27 s over six runs at
    # load 5.5 (bounds 1.84-2.16 s there, 1 s on a quiet machine, where the
    # analysis and a factorization take about half as long). On an Intel Xeon
    # (2026-11-30) its factorization took about 1 s, and a quiet fresh-clone CI
    # run measured 1.07 s; four more runs 0.02-0.97 s. So the cloth is 100 x 100
    # (30,000 unknowns): there six runs took 0.03-0.27 s, and the signal still
    # lands in an iteration (assembly, factorization or line search).
    def test_cloth_newton(self):
        run = self.run_graph({
            "grid": {"type": "MassSpringGrid", "inputs": {"vertices": [100, 100]}},
            "step": {"type": "ClothStep", "inputs": {"state": {"from": "grid.state"}, "solver": "newton",
                                                     "iterations": 1000, "substeps": 10}},
            "s": {"type": "SaveMesh", "inputs": {"mesh": {"from": "step.mesh"}, "path": "c{frame:04}.obj"}}},
            "--frames", "2", time={"start": 1, "end": 2, "fps": 30})
        # Not after="grid": a node's "done" line is printed only when it ran
        # for 0.3 s or more, and the grid is quicker on a quiet machine.
        self.interrupt("ClothStep newton 100x100", run, cpu=0.5, quiet_bound=1.0)

    # Parameterize at 2M vertices: weights, assembly, factorization, solve.
    # Not after="h": the hemisphere takes under 0.3 s on huge pages
    # (decision 29), too quick for its "done" line; at 2 CPU-seconds the
    # signal lands in Parameterize, which takes tens of them.
    def test_parameterize(self):
        run = self.run_graph({
            "h": {"type": "HemisphereMesh", "inputs": {"rings": 1000, "segments": 2000}},
            "p": {"type": "Parameterize", "inputs": {"mesh": {"from": "h.mesh"}}},
            "s": {"type": "SaveMesh", "inputs": {"mesh": {"from": "p.mesh"}, "path": "p.obj"}}})
        self.interrupt("Parameterize 2M vertices", run, cpu=2.0)

    # Generators: GridMesh at its largest (4096², 16.8M vertices), in its loops.
    def test_grid_mesh(self):
        run = self.run_graph({
            "g": {"type": "GridMesh", "inputs": {"resolution": [4096, 4096]}},
            "s": {"type": "SaveMesh", "inputs": {"mesh": {"from": "g.mesh"}, "path": "g.ply"}}})
        self.interrupt("GridMesh 4096x4096", run, cpu=0.3)

    # Procedural maps: HeightMap 8192² (bricks), in its rows.
    def test_height_map(self):
        run = self.run_graph({
            "h": {"type": "HeightMap", "inputs": {"size": [8192, 8192]}},
            "n": {"type": "HeightToNormalMap", "inputs": {"height": {"from": "h.image"}}},
            "s": {"type": "SaveImage", "inputs": {"image": {"from": "n.image"}, "path": "n.exr"}}})
        self.interrupt("HeightMap 8192x8192", run, cpu=0.3)

    # PathTrace at 16,384 spp: cancellation is asked before every sample.
    def test_path_trace_samples(self):
        run = self.run_graph({
            "box": {"type": "CornellBox"},
            "t": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}, "size": [640, 480], "spp": 16384}},
            "s": {"type": "SaveImage", "inputs": {"image": {"from": "t.image"}, "path": "t.png"}}})
        self.interrupt("PathTrace 640x480 16384 spp", run, cpu=1.5)

    # PathTrace's scene set-up and BVH build for 4.5M triangles (the grid
    # itself takes about 0.4 s, 1.4 s of CPU before decision 29's huge pages;
    # the node 3.5-4 s, of which the whole process used about 4.5 CPU-s, so
    # the signal comes at 1.5): the copies to world space ask between chunks,
    # Embree's build through its progress monitor.
    # Before: 5.3-5.6 s (the watchdog).
    def test_path_trace_bvh(self):
        run = self.run_graph({
            "g": {"type": "GridMesh", "inputs": {"resolution": [1500, 1500]}},
            "o": {"type": "Object", "inputs": {"mesh": {"from": "g.mesh"}}},
            "t": {"type": "PathTrace", "inputs": {"scene": {"from": "o.scene"}, "size": [64, 64], "spp": 1}},
            "s": {"type": "SaveImage", "inputs": {"image": {"from": "t.image"}, "path": "t.png"}}})
        self.interrupt("PathTrace BVH of 4.5M triangles", run, cpu=1.5)

    # Render (OSMesa) of 4.5M triangles at 1080p with a shadow map, at its
    # second frame (a light that changes with time): the upload asks between
    # vertex arrays, the shadow and main passes between batches of 2^18
    # triangles (each finished first). Before: 5 s, the watchdog. The second
    # frame, because the first pays what cannot be interrupted: llvmpipe
    # compiles a program at its first draw and the 4x MSAA targets are made
    # (1.7-2.2 s on the quiet machine, over 5 s on a loaded one; issue 37
    # stays open for it, docs/robustness.md); later frames reuse both.
    def test_render(self):
        run = self.run_graph({
            "g": {"type": "GridMesh", "inputs": {"resolution": [1500, 1500]}},
            "o": {"type": "Object", "inputs": {"mesh": {"from": "g.mesh"}}},
            "time": {"type": "Time"},
            "i": {"type": "Math", "inputs": {"a": {"from": "time.seconds"}, "b": 10}},
            "l": {"type": "Light", "inputs": {"intensity": {"from": "i.result"}}},
            "m": {"type": "MergeScenes", "inputs": {"a": {"from": "o.scene"}, "b": {"from": "l.scene"}}},
            "t": {"type": "Render", "inputs": {"scene": {"from": "m.scene"}, "width": 1920, "height": 1080}},
            "s": {"type": "SaveImage", "inputs": {"image": {"from": "t.image"}, "path": "t{frame:04}.exr"}}},
            "--frames", "1-3", time={"start": 1, "end": 3, "fps": 1})
        # Bound 1 s, not 0.5: on the quiet machine the exit took 0.27-0.39 s,
        # but llvmpipe's rasterizer threads, which finish a batch before the
        # check, slow more than the load factor says (1.15 s at load 4).
        self.interrupt("Render 4.5M triangles at 1080p, 2nd frame", run, after="[s] wrote", delay=0.3,
                       whole=lambda path: os.path.basename(path) == "t0001.exr", quiet_bound=1.0)

    # SaveImage of a 16384² PNG: the conversion runs in bands of rows and the
    # encoder is fed bands of scanlines, each band asked first; the staging
    # file goes. Before: 5.8 s (the watchdog; OpenCV's one encoder call).
    def test_save_image(self):
        run = self.run_graph({
            "c": {"type": "Checkerboard", "inputs": {"size": [16384, 16384]}},
            "s": {"type": "SaveImage", "inputs": {"image": {"from": "c.image"}, "path": "c.png"}}})
        self.interrupt("SaveImage 16384² PNG", run, after="c", delay=1.0)

    # An MPM emitter of 12M particles: the lattice, the inside test, the
    # Morton sort (a radix sort in passes) and the particles' set-up each ask
    # between chunks. Before: 5.2 s (the watchdog).
    def test_mpm_emitter(self):
        run = self.run_graph({
            "e": {"type": "MPMEmitSphere", "inputs": {"dimension": 3, "radius": 0.45, "spacing": 0.003}},
            "p": {"type": "MPMPoints", "inputs": {"state": {"from": "e.particles"}}},
            "s": {"type": "SavePoints", "inputs": {"points": {"from": "p.points"}, "path": "p.ply"}}})
        self.interrupt("MPMEmitSphere 12M particles", run, cpu=1.0)

    # A sweep of 100,000 quick points (at 300,000 the exit took 0.39-0.99 s,
    # around the 0.5-s target even on the quiet machine: issue 37 stays open
    # for it): the signal comes between points; a
    # cancelled sweep writes no tables (--sweep-collect writes them from the
    # points' files); each point.json left is whole.
    def test_sweep(self):
        def whole_point(path):
            if os.path.basename(path) != "point.json":
                return False
            with open(path) as f:
                return json.load(f)["status"] in ("ok", "cancelled")
        run = self.run_graph({
            "m": {"type": "Math", "inputs": {"a": 0, "b": 1}},
            "p": {"type": "Print", "inputs": {"value": {"from": "m.result"}}}},
            "--sweep", "m.a=0:1:1000", "--sweep", "m.b=0:1:100", "--record", "m.result", "-q",
            env={"LOOM_MAX_SWEEP_POINTS": "300000"})
        self.interrupt("sweep of 100,000 points", run, whole=whole_point)
        self.assertIn("--sweep-collect writes them", run.stderr())

    # A Python body that never asks ctx.cancelled() (py.loomtest_nodes.Spin).
    @unittest.skipUnless(PYTHON_PLUGIN, "Loom was built without its python plugin")
    def test_python_body(self):
        run = self.run_graph(self.spin, env={"LOOM_PYTHON_PATH": self.python_nodes})
        self.interrupt("Python body (never checks)", run)

    # --watch during a run (the same body): the watch's run gets the signal.
    @unittest.skipUnless(PYTHON_PLUGIN, "Loom was built without its python plugin")
    def test_watch_during_a_run(self):
        run = Run([self.graph(self.spin), "--watch", "--out", self.out, "--no-cache"],
                  env={"LOOM_PYTHON_PATH": self.python_nodes})
        self.interrupt("--watch, during a run", run)

    # --watch waiting for a change ends at once, exit 0 (a graph replaced by
    # a FIFO is refused at once, exit 2: tests/farm/reliability_test.py).
    def test_watch_while_waiting(self):
        g = self.graph({"m": {"type": "Math", "inputs": {"a": 1, "b": 2}},
                        "p": {"type": "Print", "inputs": {"value": {"from": "m.result"}}}})
        run = Run([g, "--watch", "--out", self.out, "--no-cache"])
        self.assertTrue(run.wait_for_line("watching"), run.stderr())
        time.sleep(1)
        seconds = run.interrupt()
        bound = QUIET_BOUND * load_factor()
        self.figures.append(("--watch, waiting", seconds, bound))
        self.assertEqual(run.proc.returncode, 0, run.stderr())
        self.assertLessEqual(seconds, bound)

    python_nodes = os.path.join(SOURCE, "python", "tests", "nodes")
    spin = {"spin": {"type": "py.loomtest_nodes.Spin", "inputs": {"seconds": 60}},
            "p": {"type": "Print", "inputs": {"value": {"from": "spin.spun"}}}}


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    for name, seconds, bound in CtrlCTest.figures:
        print(f"{name:40s} {seconds:5.2f} s  (bound {bound:.2f} s)")
    sys.exit(0 if result.wasSuccessful() else 1)
