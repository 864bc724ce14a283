"""Every capability with every other: graph features (rows) run by every driver
(columns). Each cell writes the files (or values) of one plain `loom run` of
the same graph and values, byte for byte, or is refused at validation with its
reason (docs/architecture.md, "One view of a graph"). Prints the matrix it ran
and a closing count.

Usage: matrix_test.py LOOM SOURCE_DIR TEST_PLUGIN_DIR [--only ROW,...] [--drivers COL,...]
A new graph feature adds a row (FEATURES), a new driver a column (DRIVERS).
"""
import filecmp
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

LOOM, SOURCE, TEST_PLUGINS = map(os.path.abspath, sys.argv[1:4])
ARGS = sys.argv[4:]
sys.path.insert(0, os.path.join(SOURCE, "tests", "farm"))
import slurm_cluster  # noqa: E402

BUILD = os.path.dirname(os.path.dirname(os.path.realpath(LOOM)))
ENV = dict(os.environ, LOOM_PLUGIN_PATH=TEST_PLUGINS)
MPIEXEC = shutil.which("mpiexec")
MPI_ENV = dict(ENV, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
# Core binding left to mpiexec's default where it can bind (a driver must not
# change a file's bytes by the cores it sees: SaveVideo's MP4 included).
MPI_ARGS = ["--oversubscribe", "--mca", "btl", "self,vader", "--mca", "oob_tcp_if_include", "lo",
            "--mca", "btl_vader_single_copy_mechanism", "none"]


class Refused(Exception):
    """A documented refusal: the combination is refused at validation, with this reason."""


class NotApplicable(Exception):
    """The row has nothing this column exercises (e.g. no frames to split)."""


class Skipped(Exception):
    """The service a column needs cannot be had here (the reason says why)."""


def run(cmd, env=ENV, timeout=240, check=True, cwd=None):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout, env=env, cwd=cwd)
    if check and p.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, cmd))}: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-3000:]}")
    return p


def loom(*args, **kw):
    return run([LOOM, *args], **kw)


def write_json(path, doc):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return path


def output_files(folder):
    """Relative paths of the files a run wrote (Loom's own folders left out)."""
    files = []
    for root, dirs, names in os.walk(folder):
        dirs[:] = [d for d in dirs if not d.startswith(".loom")]
        for n in names:
            files.append(os.path.relpath(os.path.join(root, n), folder))
    return sorted(files)


def same_files(reference, folder, only=None):
    """Raises AssertionError unless `folder` holds the files of `reference`, byte for byte."""
    want = [f for f in output_files(reference) if only is None or only(f)]
    got = [f for f in output_files(folder) if only is None or only(f)]
    if not want:
        raise AssertionError(f"the reference run wrote nothing in {reference}")
    if want != got:
        raise AssertionError(f"files differ: reference {want}, got {got}")
    for f in want:
        if not filecmp.cmp(os.path.join(reference, f), os.path.join(folder, f), shallow=False):
            raise AssertionError(f"{f}: bytes differ from the plain run's")


# --- graph features: each writes its graph (and the files it is made from) ------

class Feature:
    """A graph written for the matrix. `interface`/`inner`: an address --set,
    --sweep and Python's set= take, with a value (None: the row has none);
    `record`: an output for --target and --record; `frames`: a sub-range of a
    graph over frames; `edits`: files a --watch run must follow, each with an
    edit that changes the result."""
    frames = None
    interface = None
    inner = None
    sequence = None  # a file gathering the whole range (compared over whole runs only)
    tiled = False

    def __init__(self, folder):
        self.folder = folder
        self.edits = []
        self.graph = self.write()


def doc(nodes, groups=None, time_range=None, version=2):
    d = {"loom": version, "seed": 5, "nodes": nodes}
    if groups:
        d["groups"] = groups
    if time_range:
        d["time"] = {"start": time_range[0], "end": time_range[1], "fps": 24}
    return d


LOOK = {"description": "a board and a random number",
        "inputs": {"cells": {"type": "Int", "default": 4, "min": 1, "max": 64, "to": ["board.cells"]}},
        "outputs": {"image": {"from": "board.image"}, "value": {"from": "rand.value"}},
        "nodes": {"board": {"type": "Checkerboard", "inputs": {"size": [24, 24]}},
                  "rand": {"type": "Random"}}}


def look_sinks(source):
    return {"save": {"type": "SaveImage", "inputs": {"image": {"from": f"{source}.image"}, "path": "board.png"}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": f"{source}.value"}, "path": "rand.txt"}}}


class Plain(Feature):
    name = "plain nodes"
    interface = ("board.cells", 6)
    record = "rand.value"

    def write(self):
        nodes = dict(LOOK["nodes"])
        nodes["board"] = {"type": "Checkerboard", "inputs": {"size": [24, 24], "cells": 4}}
        path = os.path.join(self.folder, "g.json")
        self.edits.append(("graph file", path, lambda d: d["nodes"]["board"]["inputs"].update(cells=2)))
        return write_json(path, doc({**nodes, **look_sinks_plain()}, version=1))


def look_sinks_plain():
    return {"save": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "board.png"}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": "rand.value"}, "path": "rand.txt"}}}


class InlineGroup(Feature):
    name = "inline group"
    interface = ("look.cells", 6)
    inner = ("look.board.size", [20, 20])
    record = "look.value"

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"),
                          doc({"look": {"type": "Look", "inputs": {"cells": 4}}, **look_sinks("look")}, {"Look": LOOK}))


class GroupFile(Feature):
    name = "group file"
    interface = ("look.cells", 6)
    inner = ("look.board.size", [20, 20])
    record = "look.image"

    def write(self):
        group = write_json(os.path.join(self.folder, "parts", "look.json"), {"loom": 2, **LOOK})
        self.edits.append(("group file", group, lambda d: d["nodes"]["board"]["inputs"].update(size=[16, 16])))
        return write_json(os.path.join(self.folder, "g.json"),
                          doc({"look": {"type": "parts/look.json", "inputs": {"cells": 4}}, **look_sinks("look")}))


class LibraryGroup(Feature):
    name = "library group (studio)"
    interface = ("look.width", 40)
    inner = ("look.render.samples", 1)
    record = "look.image"

    def write(self):
        nodes = {"ball": {"type": "UVSphere", "inputs": {"rings": 8, "segments": 12}},
                 "paint": {"type": "Material"},
                 "look": {"type": "studio", "inputs": {"mesh": {"from": "ball.mesh"}, "material": {"from": "paint.material"},
                                                       "width": 32, "height": 24}},
                 "save": {"type": "SaveImage", "inputs": {"image": {"from": "look.image"}, "path": "studio.png"}}}
        return write_json(os.path.join(self.folder, "g.json"), doc(nodes))


class SearchPathGroup(Feature):
    name = "library group (LOOM_GRAPH_PATH)"
    interface = ("look.cells", 6)
    inner = ("look.board.size", [20, 20])
    record = "look.value"

    def write(self):
        group = write_json(os.path.join(self.folder, "library", "lookalike.json"), {"loom": 2, **LOOK})
        self.edits.append(("library group", group, lambda d: d["inputs"]["cells"].update(default=9)))
        return write_json(os.path.join(self.folder, "g.json"),
                          doc({"look": {"type": "lookalike"}, **look_sinks("look")}))

    def env(self):
        return {"LOOM_GRAPH_PATH": os.path.join(self.folder, "library")}


class NestedGroups(Feature):
    name = "nested groups"
    interface = ("o.cells", 7)
    inner = ("o.inner.board.size", [20, 20])
    record = "o.value"

    def write(self):
        outer = {"inputs": {"cells": {"type": "Int", "default": 3, "to": ["inner.cells"]}},
                 "outputs": {"image": {"from": "inner.image"}, "value": {"from": "inner.value"}},
                 "nodes": {"inner": {"type": "Look"}}}
        return write_json(os.path.join(self.folder, "g.json"),
                          doc({"o": {"type": "Outer", "inputs": {"cells": 5}}, **look_sinks("o")},
                              {"Look": LOOK, "Outer": outer}))


HALVE = {"inputs": {"x": {"type": "Float", "default": 0, "to": ["half.a"]}},
         "outputs": {"x": {"from": "half.result"}},
         "nodes": {"half": {"type": "Math", "inputs": {"b": 0.5, "op": "multiply"}}}}


class RepeatLiteral(Feature):
    name = "Repeat (count literal)"
    interface = ("loop.count", 5)
    record = "loop.x"

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "loop": {"type": "Repeat", "body": "Halve", "inputs": {"count": 3, "x": 1024}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": "loop.x"}, "path": "x.txt"}}}, {"Halve": HALVE}))


class RepeatLinked(Feature):
    name = "Repeat (count linked)"
    interface = ("n.value", 4)
    record = "loop.x"

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "n": {"type": "IntConstant", "inputs": {"value": 2}},
            "loop": {"type": "Repeat", "body": "Halve", "inputs": {"count": {"from": "n.value"}, "x": 1000}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": "loop.x"}, "path": "x.txt"}}}, {"Halve": HALVE}))


PY_MODULE = '''import loom


@loom.node(inputs={"x": loom.In("Float", 1.0, "a number")}, outputs={"y": loom.Out("Float", "x * FACTOR + 1")})
def Scale(x):
    """x times a factor, plus one."""
    return x * FACTOR + 1
'''


class PythonNode(Feature):
    name = "Python node (module)"
    interface = ("scale.x", 2.5)
    record = "scale.y"

    def write(self):
        module = os.path.join(self.folder, "pynodes", "matrixnodes.py")
        os.makedirs(os.path.dirname(module))
        with open(module, "w") as f:
            f.write(PY_MODULE.replace("FACTOR", "3"))
        self.edits.append(("Python module", module, PY_MODULE.replace("FACTOR", "7")))
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "scale": {"type": "py.matrixnodes.Scale", "inputs": {"x": 1.5}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": "scale.y"}, "path": "y.txt"}}}, version=1))

    def env(self):
        return {"LOOM_PYTHON_PATH": os.path.join(self.folder, "pynodes")}


class Simulation(Feature):
    name = "simulation over frames"
    interface = ("sim.v", 3.0)
    record = "sim.x"
    frames = "3-4"

    def write(self):
        number = os.path.join(self.folder, "start.txt")
        with open(number, "w") as f:
            f.write("0.5\n")
        self.edits.append(("input file", number, "2.5\n"))
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "x0": {"type": "ReadNumber", "inputs": {"path": "start.txt"}},
            "sim": {"type": "Integrate", "inputs": {"x": {"from": "x0.value"}, "v": 2.0}},
            "text": {"type": "WriteText", "inputs": {"value": {"from": "sim.x"}, "path": "x_{frame:02}.txt"}}},
            time_range=(1, 6), version=1))


class Tiled(Feature):
    name = "tiled node (PathTrace)"
    interface = ("trace.spp", 2)
    record = "trace.image"
    tiled = True

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "box": {"type": "CornellBox"},
            "trace": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}, "size": [24, 20], "spp": 4}},
            "save": {"type": "SaveImage", "inputs": {"image": {"from": "trace.image"}, "path": "box.exr"}}}, version=1))


class Sequence(Feature):
    name = "sequence sink (SaveVideo)"
    interface = ("board.cells", 3)
    record = "power.result"
    frames = "2-3"
    sequence = "twist.mp4"

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "board": {"type": "Checkerboard", "inputs": {"size": [32, 32], "cells": 4}},
            "time": {"type": "Time"},
            "power": {"type": "Math", "inputs": {"a": {"from": "time.seconds"}, "b": 1.0, "op": "add"}},
            "twist": {"type": "ImageWarp", "inputs": {"image": {"from": "board.image"}, "method": "idw",
                                                      "pairs": [[8, 8, 10, 6], [24, 24, 20, 26]],
                                                      "idw_power": {"from": "power.result"}}},
            "frame": {"type": "SaveImage", "inputs": {"image": {"from": "twist.image"}, "path": "f_{frame:02}.png"}},
            "video": {"type": "SaveVideo", "inputs": {"image": {"from": "twist.image"}, "path": "twist.mp4"}}},
            time_range=(1, 5), version=1))


class Volume(Feature):
    name = "volume sink over frames (SaveVDB)"
    interface = ("volume.voxel_size", 0.05)
    record = "sim.substeps"
    frames = "2-3"

    def write(self):
        return write_json(os.path.join(self.folder, "g.json"), doc({
            "emit": {"type": "MPMEmitBox", "inputs": {"dimension": 3, "min": [0.4, 0.5, 0.4], "max": [0.6, 0.7, 0.6],
                                                      "material": "fluid", "sampling": "grid", "spacing": 0.05}},
            "sim": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 16}},
            "points": {"type": "MPMPoints", "inputs": {"state": {"from": "sim.state"}}},
            "volume": {"type": "PointsToVolume", "inputs": {"points": {"from": "points.points"}, "voxel_size": 0.0625}},
            "save": {"type": "SaveVDB", "inputs": {"volume": {"from": "volume.volume"}, "path": "v_{frame:02}.vdb"}}},
            time_range=(1, 4), version=1))


FEATURES = [Plain, InlineGroup, GroupFile, LibraryGroup, SearchPathGroup, NestedGroups, RepeatLiteral, RepeatLinked, PythonNode,
            Simulation, Tiled, Sequence, Volume]


# --- drivers: each runs a feature's graph its way and compares ------------------

def feature_env(feature):
    # os.environ now, not at start: the private Slurm cluster sets SLURM_CONF when it starts.
    return dict(os.environ, LOOM_PLUGIN_PATH=TEST_PLUGINS, **(feature.env() if hasattr(feature, "env") else {}))


def reference(feature, work, *args, fresh=False):
    """The plain `loom run` (no disk cache) of the feature with `args`: its output folder."""
    out = os.path.join(work, "reference-" + str(abs(hash(args))) + ("-fresh" if fresh else ""))
    if fresh or not os.path.isdir(out):
        loom("run", feature.graph, "--out", out, "--no-cache", "-q", *args, env=feature_env(feature))
    return out


def target_value(feature, work, *args):
    p = loom("run", feature.graph, "--out", os.path.join(work, "t"), "--no-cache", "-q", "--json",
             "--target", feature.record, *args, env=feature_env(feature))
    return json.loads(p.stdout)


def d_frames(feature, work):
    if not feature.frames:
        raise NotApplicable("one frame")
    out = os.path.join(work, "frames")
    loom("run", feature.graph, "--out", out, "--no-cache", "-q", "--frames", feature.frames, env=feature_env(feature))
    ref = reference(feature, work)
    first, last = map(int, feature.frames.split("-"))
    wanted = [f for f in output_files(ref) if any(f"_{k:02}." in f for k in range(first, last + 1))]
    if not wanted:
        raise AssertionError("no per-frame files in the reference")
    for f in wanted:
        if not filecmp.cmp(os.path.join(ref, f), os.path.join(out, f), shallow=False):
            raise AssertionError(f"{f} differs from the whole run's frame")


def sweep_cell(feature, work, address):
    if not address:
        raise NotApplicable("no such address")
    name, value = address
    out = os.path.join(work, "sweep-" + name)
    loom("run", feature.graph, "--out", out, "--no-cache", "-q", "--sweep", f"{name}={json.dumps(value)}",
         env=feature_env(feature))
    same_files(reference(feature, work, "--set", f"{name}={json.dumps(value)}"), os.path.join(out, "points", "0000"),
               only=lambda f: f != "point.json")


def d_sweep_interface(feature, work):
    sweep_cell(feature, work, feature.interface)


def d_sweep_inner(feature, work):
    if feature.inner is None and feature.name.startswith("Repeat"):
        raise Refused("a Repeat body's nodes are not nodes of the graph (docs/graph-format.md, Repeat)")
    sweep_cell(feature, work, feature.inner)


def d_record(feature, work):
    name, value = feature.interface
    out = os.path.join(work, "record")
    loom("run", feature.graph, "--out", out, "--no-cache", "-q", "--sweep", f"{name}={json.dumps(value)}",
         "--record", feature.record, env=feature_env(feature))
    with open(os.path.join(out, "sweep.json")) as f:
        records = json.load(f)["points"][0]["records"]
    want = target_value(feature, work, "--set", f"{name}={json.dumps(value)}")
    if records != want:
        raise AssertionError(f"--record gave {records}, --target {want}")


def d_cache_rerun(feature, work):
    cache = os.path.join(work, "cache")
    for k in (1, 2):
        out = os.path.join(work, f"cached-{k}")
        loom("run", feature.graph, "--out", out, "-q", "--cache", cache, "--cache-min-seconds", "0",
             "--profile", os.path.join(work, f"profile-{k}.json"), env=feature_env(feature))
        same_files(reference(feature, work), out)
    with open(os.path.join(work, "profile-2.json")) as f:
        nodes = json.load(f)["nodes"]
    for id, n in nodes.items():  # a cached result reports what computing it took
        if n["status"] == "cached" and n.get("source") == "disk" and not n["compute_seconds"] > 0:
            raise AssertionError(f"{id}: read from the disk cache but compute_seconds {n['compute_seconds']}")


def submit_cell(feature, work, to):
    out = os.path.join(work, "submit-" + to)
    args = ["submit", feature.graph, "--to", to, "--out", out, "--chunk", "2", "-j", "2"]
    if to == "local":
        # The job runs from its folder alone: the group files the graph was made
        # from are moved away between writing the job and running it.
        loom(*args, "--dry-run", env=feature_env(feature))
        away = [p for p in (os.path.join(feature.folder, d) for d in ("parts", "library")) if os.path.isdir(p)]
        for p in away:
            os.rename(p, p + ".away")
        try:
            p = loom("jobs", "resume", os.path.join(out, ".loom-job"), "-j", "2", env=feature_env(feature),
                     check=False, timeout=300)
        finally:
            for p_ in away:
                os.rename(p_ + ".away", p_)
    else:
        p = loom(*args, env=feature_env(feature), check=False, timeout=300)
    if p.returncode != 0:
        raise AssertionError(f"loom submit: exit {p.returncode}\n{p.stderr[-3000:]}")
    if to == "slurm":
        CLUSTER.wait_idle(timeout=120)
        status = loom("jobs", "status", os.path.join(out, ".loom-job"), check=False, env=feature_env(feature))
        counts = re.search(r"(\d+) tasks: (\d+) done", status.stdout)
        if status.returncode != 0 or not counts or counts.group(1) != counts.group(2):
            raise AssertionError("not every task is done:\n" + status.stdout + status.stderr)
    same_files(reference(feature, work), out)


def d_submit_local(feature, work):
    submit_cell(feature, work, "local")


CLUSTER = None


def d_submit_slurm(feature, work):
    global CLUSTER
    if CLUSTER is None:
        reason = slurm_cluster.unavailable_reason()
        if reason:
            CLUSTER = reason
        else:
            CLUSTER = slurm_cluster.SlurmCluster()
            CLUSTER.start()
    if isinstance(CLUSTER, str):
        raise Skipped(CLUSTER)
    submit_cell(feature, work, "slurm")


def mpi_cell(feature, work, split, *extra):
    if not MPIEXEC:
        raise Skipped("mpiexec is not installed (openmpi-bin; scripts/install-deps)")
    if not os.path.exists(os.path.join(BUILD, "lib", "libloom_mpi.so")):
        raise Skipped("loom was built without MPI")
    out = os.path.join(work, "mpi-" + split + "".join(extra))
    run([MPIEXEC, "-n", "2", *MPI_ARGS, LOOM, "run", feature.graph, "--out", out, "--no-cache", "-q", "--mpi-split", split,
         *extra],
        env=dict(MPI_ENV, **(feature.env() if hasattr(feature, "env") else {})))
    same_files(reference(feature, work), out)


def d_mpi_frames(feature, work):
    mpi_cell(feature, work, "frames")


def d_mpi_tiles(feature, work):
    mpi_cell(feature, work, "tiles")


def d_mpi_tiles_dealt(feature, work):
    mpi_cell(feature, work, "tiles", "--mpi-deal", "dynamic")


def d_mpi_frames_dealt(feature, work):
    """Frames handed out as ranks ask (one at a time, or runs of them past 16
    a rank): each part a session.evaluate of its own, simulations' states and
    sequence sinks as for blocks."""
    mpi_cell(feature, work, "frames", "--mpi-deal", "dynamic")


def d_mpi_samples(feature, work):
    mpi_cell(feature, work, "samples")


def d_mpi_samples_dealt(feature, work):
    """Each sample pass cut into 256 slots that the ranks take as they ask."""
    mpi_cell(feature, work, "samples", "--mpi-deal", "dynamic")


def wait_for(predicate, seconds, what):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def written_now(folder):
    """The whole files in `folder` while a watching run writes there: its
    staging files (".loomtmp-...", renamed into place or removed at any
    moment) are not outputs yet. The final comparison (same_files) still sees
    any staging file left behind."""
    files = {}
    for f in output_files(folder):
        if os.path.basename(f).startswith(".loomtmp-"):
            continue
        with open(os.path.join(folder, f), "rb") as stream:
            files[f] = stream.read()
    return files


def d_watch(feature, work):
    if not feature.edits:
        raise NotApplicable("no file to edit in this row (the graph file's edit is the plain row's)")
    out = os.path.join(work, "watch")
    originals = {path: open(path).read() for _, path, _ in feature.edits}
    proc = subprocess.Popen([LOOM, "run", feature.graph, "--out", out, "--no-cache", "--watch"], env=feature_env(feature),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        runs = lambda: len([f for f in output_files(out)]) > 0  # noqa: E731
        wait_for(runs, 60, "the first run")
        time.sleep(0.5)
        for kind, path, edit in feature.edits:
            before = written_now(out)
            if callable(edit):
                with open(path) as f:
                    d = json.load(f)
                edit(d)
                text = json.dumps(d)
            else:
                text = edit
            with open(path, "w") as f:
                f.write(text)

            def changed():
                return written_now(out) != before
            wait_for(changed, 30, f"a run after the {kind} changed")
            time.sleep(0.5)
        same_files(reference(feature, work, fresh=True), out)
    finally:
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=10)
        for path, text in originals.items():  # the later columns compare against the files as written
            with open(path, "w") as f:
                f.write(text)


def d_preview(feature, work):
    """`--preview`: the partial images a node publishes go to the preview file
    and nowhere else; the run's own files are the plain run's."""
    out, preview = os.path.join(work, "preview-out"), os.path.join(work, "preview.png")
    loom("run", feature.graph, "--out", out, "--no-cache", "-q", "--preview", preview, "--preview-every", "0",
         env=feature_env(feature))
    same_files(reference(feature, work), out)
    publishes = feature.tiled  # PathTrace publishes its passes; no other row's node does
    if publishes != os.path.exists(preview):
        raise AssertionError(f"preview file {'missing' if publishes else 'written'}: {preview}")


PY_RUN = '''
import json, sys, loom
graph, out, address, value = sys.argv[1:5]
g = loom.load(graph)
loom.Session(disk_cache=False, output_dir=out).run(g, set={address: json.loads(value)})
'''


def d_python(feature, work):
    python = "/usr/bin/python3"
    module_dir = os.path.join(BUILD, "python")
    if not os.path.isdir(os.path.join(module_dir, "loom")):
        raise Skipped("the Python module was not built (pybind11-dev)")
    name, value = feature.interface
    out = os.path.join(work, "python")
    env = dict(feature_env(feature), PYTHONPATH=module_dir)
    run([python, "-c", PY_RUN, feature.graph, out, name, json.dumps(value)], env=env)
    same_files(reference(feature, work, "--set", f"{name}={json.dumps(value)}"), out)


def d_editor(feature, work):
    """The editor's "Write outputs": the graph in the editor's document model, evaluated by its controller."""
    program = os.path.join(BUILD, "bin", "editor_write_outputs")
    if not os.path.exists(program):
        raise Skipped("the editor was not built (ImGui, GLFW: scripts/install-deps)")
    out = os.path.join(work, "editor")
    run([program, feature.graph, out], env=feature_env(feature))
    same_files(reference(feature, work), out)


DRIVERS = [("frames", d_frames), ("sweep iface", d_sweep_interface), ("sweep inner", d_sweep_inner),
           ("record", d_record), ("cache rerun", d_cache_rerun), ("submit local", d_submit_local),
           ("submit slurm", d_submit_slurm), ("mpi frames", d_mpi_frames), ("mpi tiles", d_mpi_tiles),
           ("mpi tiles dealt", d_mpi_tiles_dealt), ("mpi frames dealt", d_mpi_frames_dealt),
           ("mpi samples", d_mpi_samples), ("mpi samples dealt", d_mpi_samples_dealt), ("watch", d_watch), ("preview", d_preview), ("python", d_python),
           ("editor", d_editor)]


# --- refusals: what cannot be combined is refused by `loom validate` -------------

def refusals(work):
    """(what, passed, detail) for each combination validation must refuse with its reason."""
    cases = []
    sim_body = {"inputs": {"x": {"type": "Float", "default": 0, "to": ["sim.x"]}},
                "outputs": {"x": {"from": "sim.x"}}, "nodes": {"sim": {"type": "Integrate"}}}
    g = write_json(os.path.join(work, "refuse", "sim-in-repeat.json"),
                   doc({"loop": {"type": "Repeat", "body": "Sim", "inputs": {"count": 2}}}, {"Sim": sim_body}))
    cases.append(("a simulation inside a Repeat body", g, "cannot step time"))
    for what, graph, reason in cases:
        p = loom("validate", graph, check=False)
        ok = p.returncode == 2 and reason in p.stderr
        yield what, ok, p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"


def invariants(work):
    """(what, passed, detail): rules across rows. Grouping nodes — inline, in a
    group file, nested — keeps their random numbers (issue 35, finding 11)."""
    folder = os.path.join(work, "grouping")
    rand = {"rand": {"type": "Random"}, "text": {"type": "WriteText", "inputs": {"value": {"from": "rand.value"}, "path": "r.txt"}}}
    wrapped = {"outputs": {"value": {"from": "rand.value"}}, "nodes": {"rand": {"type": "Random"}}}
    write_json(os.path.join(folder, "wrapped.json"), {"loom": 2, **wrapped})
    sink = {"text": {"type": "WriteText", "inputs": {"value": {"from": "w.value"}, "path": "r.txt"}}}
    graphs = {"plain": doc(rand, version=1),
              "inline group": doc({"w": {"type": "Wrapped"}, **sink}, {"Wrapped": wrapped}),
              "group file": doc({"w": {"type": "wrapped.json"}, **sink}),
              "nested groups": doc({"w": {"type": "Outer"}, **sink},
                                   {"Wrapped": wrapped, "Outer": {"outputs": {"value": {"from": "in.value"}},
                                                                  "nodes": {"in": {"type": "Wrapped"}}}})}
    texts = {}
    for name, d in graphs.items():
        g = write_json(os.path.join(folder, name.replace(" ", "-") + ".json"), d)
        out = os.path.join(folder, "out-" + name.replace(" ", "-"))
        loom("run", g, "--out", out, "--no-cache", "-q")
        with open(os.path.join(out, "r.txt")) as f:
            texts[name] = f.read().strip()
    same = len(set(texts.values())) == 1
    yield "grouping a node keeps its random numbers", same, ", ".join(f"{k}: {v}" for k, v in texts.items())


def main():
    only = drivers = None
    if "--only" in ARGS:
        only = ARGS[ARGS.index("--only") + 1].split(",")
    if "--drivers" in ARGS:
        drivers = ARGS[ARGS.index("--drivers") + 1].split(",")
    root = tempfile.mkdtemp(prefix="loom-matrix-")
    counts = {"passed": 0, "failed": 0, "refused": 0, "skipped": 0, "n/a": 0}
    rows, failures = [], []
    columns = [(n, f) for n, f in DRIVERS if drivers is None or n in drivers]
    try:
        for cls in FEATURES:
            if only and cls.__name__ not in only:
                continue
            work = os.path.join(root, cls.__name__)
            os.makedirs(work)
            feature = cls(work)
            row = []
            try:
                reference(feature, work)
            except AssertionError as e:
                failures.append((cls.name, "plain run", str(e)))
                rows.append((cls.name, ["FAIL"] * len(columns)))
                counts["failed"] += len(columns)
                continue
            for name, driver in columns:
                cell = os.path.join(work, name.replace(" ", "-"))
                os.makedirs(cell)
                start = time.monotonic()
                try:
                    driver(feature, cell)
                    mark = "ok"
                    counts["passed"] += 1
                except Refused as e:
                    mark = "refused"
                    counts["refused"] += 1
                    failures.append((cls.name, name, "refused (documented): " + str(e)))
                except NotApplicable:
                    mark = "-"
                    counts["n/a"] += 1
                except Skipped as e:
                    mark = "skip"
                    counts["skipped"] += 1
                    failures.append((cls.name, name, "skipped: " + str(e)))
                except (AssertionError, subprocess.TimeoutExpired, OSError, json.JSONDecodeError, KeyError) as e:
                    mark = "FAIL"
                    counts["failed"] += 1
                    failures.append((cls.name, name, str(e)))
                row.append(f"{mark} {time.monotonic() - start:4.1f}s" if mark in ("ok", "FAIL") else mark)
            rows.append((cls.name, row))
            print(f"{cls.name}: {' | '.join(row)}", flush=True)
        for what, ok, detail in invariants(root):
            counts["passed" if ok else "failed"] += 1
            if not ok:
                failures.append((what, "invariant", detail))
            print(f"invariant: {what}: {'ok' if ok else 'FAIL'} ({detail})")
        for what, ok, detail in refusals(root):
            counts["passed" if ok else "failed"] += 1
            if not ok:
                failures.append((what, "validate", detail))
            print(f"refused at validation: {what}: {'ok' if ok else 'FAIL'} ({detail})")
    finally:
        if isinstance(CLUSTER, slurm_cluster.SlurmCluster):
            CLUSTER.stop()
        shutil.rmtree(root, ignore_errors=True)
    width = max(len(r[0]) for r in rows) if rows else 10
    print("\n" + " " * width + " | " + " | ".join(f"{n:>12}" for n, _ in columns))
    for name, row in rows:
        print(f"{name:<{width}} | " + " | ".join(f"{c:>12}" for c in row))
    print("\nNotes:")
    for feature, driver, text in failures:
        print(f"- {feature} × {driver}: {text}")
    print(f"\nmatrix: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped"
          f" ({counts['refused']} refused at validation, {counts['n/a']} not applicable)")
    sys.exit(1 if counts["failed"] else 0)


if __name__ == "__main__":
    main()
