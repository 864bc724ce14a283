"""`loom submit` on a private cluster of three nodes made of Linux namespaces
(netns_cluster.py), one cluster start for every case: frames spread over the
nodes, each running its own Loom from its own install folder; a node killed
mid-job, whose task Slurm requeues on another; a simulation in segments
(--sim-chunk) whose node is killed half-way; `srun --mpi=pmix` tiles, and
sample passes dealt as ranks ask, over the three nodes, each rank its node's
own loom. Usage: netns_test.py LOOM
SOURCE_DIR TEST_PLUGIN_DIR [unittest arguments]. Exits 77 (ctest's skip),
saying why, where namespaces or Slurm are not available."""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import netns_cluster

LOOM, SOURCE, TEST_PLUGINS = map(os.path.abspath, sys.argv[1:4])
del sys.argv[1:4]
os.environ["LOOM_PLUGIN_PATH"] = TEST_PLUGINS  # Sleep, WriteText, FrameNumber, TallyIntegrate
# The build every node sees at its own prefix (/opt/loom-nK); its bin/, where
# LOOM lies, is hidden from the nodes: nothing may run the submitter's path.
BUILD = os.path.dirname(os.path.dirname(os.path.abspath(LOOM)))
os.environ["PATH"] = "/usr/local/bin:" + os.environ.get("PATH", "/usr/bin:/bin")  # the nodes' loom is there


def loom(*args, check=True, timeout=300):
    p = subprocess.run([LOOM, *map(str, args)], capture_output=True, text=True, timeout=timeout)
    if check and p.returncode != 0:
        raise AssertionError(f"loom {' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def read(path, mode="r"):
    with open(path, mode) as f:
        return f.read()


def write_graph(folder, nodes, time_range):
    path = os.path.join(folder, "graph.json")
    with open(path, "w") as f:
        json.dump({"loom": 1, "seed": 3, "nodes": nodes,
                   "time": {"start": time_range[0], "end": time_range[1], "fps": 24}}, f)
    return path


def statuses(job):
    return {int(os.path.basename(p)[:4]): json.loads(read(p)) for p in glob.glob(os.path.join(job, "status", "*.json"))}


def wait_for(predicate, timeout, what):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    raise TimeoutError(what)


def files(folder):
    return sorted(f for f in os.listdir(folder) if f not in (".loom-job", ".loom-cache"))


class MultiNode(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        reason = netns_cluster.unavailable_reason()
        under_tmp = [p for p in (SOURCE, BUILD) if os.path.commonpath([p, "/tmp"]) == "/tmp"]
        if under_tmp:  # the nodes read the graphs and the build from these paths, as from a shared disk
            reason = f"{under_tmp[0]} is under /tmp, which every node has a private one of: clone elsewhere"
        if reason:
            raise unittest.SkipTest(reason)
        cls.cluster = netns_cluster.NetnsCluster(3, install=BUILD, hide=[os.path.dirname(os.path.abspath(LOOM))])
        start = time.time()
        try:
            cls.cluster.start()
        except Exception:
            cls.cluster.stop()
            raise
        print(f"\n3 nodes started in {time.time() - start:.2f} s", file=sys.stderr)

    @classmethod
    def tearDownClass(cls):
        start = time.time()
        cls.cluster.stop()
        print(f"cluster stopped in {time.time() - start:.2f} s", file=sys.stderr)

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="case-", dir=self.cluster.shared)  # every node sees it
        os.chmod(self.dir, 0o755)
        self.started = time.time()

    def tearDown(self):
        print(f"{self.id().split('.')[-1]}: {time.time() - self.started:.1f} s", file=sys.stderr)
        shutil.rmtree(self.dir, ignore_errors=True)
        for n in self.cluster.nodes:  # a case that killed a node leaves the next ones three
            if not n.pid_ns:
                self.cluster.restart_node(n)

    def submit(self, graph, out, *args):
        p = subprocess.run([LOOM, "submit", graph, "--to", "slurm", "--out", out, *map(str, args)],
                           capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        return os.path.join(out, ".loom-job")

    def running_on(self, job, task):
        """The node `task` runs on, once its `loom run` has started there."""
        def started():
            st = statuses(job).get(task, {})
            log = os.path.join(job, "logs", f"task-{task:04}.log")
            return st.get("state") == "running" and os.path.exists(log) and "attempt" in read(log) and st["host"]
        return wait_for(started, 60, f"task {task} never ran")

    def node(self, name):
        return next(n for n in self.cluster.nodes if n.name == name)

    def test_frames_spread_over_nodes_each_running_its_own_install(self):
        g = os.path.join(SOURCE, "graphs", "time-twist-sequence.json")
        out, ref = os.path.join(self.dir, "out"), os.path.join(self.dir, "ref")
        job = self.submit(g, out, "--frames", "1-8", "--chunk", "2")
        self.cluster.wait_idle(120)
        loom("run", g, "--out", ref, "--frames", "1-8", "--no-cache", "-q")
        st = statuses(job)
        self.assertEqual([s["state"] for s in st.values()], ["done"] * 5, loom("jobs", "status", job, check=False).stdout)
        hosts = {s["host"] for s in st.values()}
        self.assertTrue(hosts <= {"n1", "n2", "n3"} and len(hosts) >= 2, hosts)
        for s in st.values():  # the node's own loom, found on its PATH, not the submitter's path
            self.assertEqual(s["loom"], f"/opt/loom-{s['host']}/bin/loom")
        for f in sorted(os.listdir(os.path.join(ref, "frames"))):
            self.assertEqual(read(os.path.join(out, "frames", f), "rb"), read(os.path.join(ref, "frames", f), "rb"), f)
        self.assertEqual(read(os.path.join(out, "twist.mp4"), "rb"), read(os.path.join(ref, "twist.mp4"), "rb"))
        # The assemble task, on whichever node, read every frame from the shared cache.
        assemble = json.loads(read(os.path.join(job, "profiles", "0004.json")))["nodes"]["twist"]
        self.assertEqual((assemble["runs"], assemble["disk_hits"]), (0, 8))

    def test_a_lost_node_s_task_runs_again_on_another(self):
        g = write_graph(self.dir, {
            "f": {"type": "FrameNumber"},
            "s": {"type": "Sleep", "inputs": {"value": {"from": "f.value"}, "ms": 3000}},
            "w": {"type": "WriteText", "inputs": {"value": {"from": "s.value"}, "path": "f_{frame:02}.txt"}}}, (1, 6))
        out = os.path.join(self.dir, "out")
        job = self.submit(g, out, "--chunk", "1", "--no-cache")
        host = self.running_on(job, 1)
        time.sleep(0.5)  # inside the Sleep
        killed = time.time()
        self.cluster.kill_node(self.node(host))  # a crash: every process of the node at once
        self.cluster.wait_idle(120)
        print(f"node {host} killed: the job ended {time.time() - killed:.1f} s later", file=sys.stderr)
        st = statuses(job)
        self.assertEqual([st[i]["state"] for i in range(6)], ["done"] * 6, loom("jobs", "status", job, check=False).stdout)
        tries = st[1]["tries"]
        self.assertEqual(tries[0]["host"], host)
        self.assertTrue(tries[0]["end"].startswith("lost"), tries)
        self.assertIn("requeued by Slurm", tries[0]["end"])
        self.assertNotEqual(tries[-1]["host"], host)
        self.assertEqual(tries[-1]["end"], "done")
        self.assertEqual(st[1]["attempts"], len(tries))
        report = loom("jobs", "status", job).stdout
        self.assertIn(f"tries: {host} lost (its node failed; requeued by Slurm), {tries[-1]['host']} done", report)
        # Every frame as one `loom run` writes it (WriteText: "%f\n"), and no partial or temporary file.
        self.assertEqual(files(out), [f"f_{f:02}.txt" for f in range(1, 7)])
        for f in range(1, 7):
            self.assertEqual(read(os.path.join(out, f"f_{f:02}.txt")), f"{f:.6f}\n")

    def test_a_simulation_in_segments_loses_at_most_one_when_its_node_dies(self):
        tally = os.path.join(self.dir, "tally")
        g = write_graph(self.dir, {
            "sim": {"type": "TallyIntegrate", "inputs": {"x": 0, "v": 24, "ms": 600, "tally": tally}},
            "w": {"type": "WriteText", "inputs": {"value": {"from": "sim.x"}, "path": "x_{frame:02}.txt"}}}, (1, 12))
        out = os.path.join(self.dir, "out")
        job = self.submit(g, out, "--chunk", "6", "--sim-chunk", "4")
        tasks = json.loads(read(os.path.join(job, "manifest.json")))["tasks"]
        self.assertEqual([(t["name"], t["wave"]) for t in tasks][:3],
                         [("simulate sim 1-4", 0), ("simulate sim 5-8", 1), ("simulate sim 9-12", 2)])
        host = self.running_on(job, 1)
        wait_for(lambda: os.path.exists(tally) and read(tally).split().count("7"), 60, "frame 7 never started")
        self.cluster.kill_node(self.node(host))  # half-way: frames 5 and 6 stored, 7 being stepped
        self.cluster.wait_idle(150)
        st = statuses(job)
        self.assertEqual([s["state"] for s in st.values()], ["done"] * 5, loom("jobs", "status", job, check=False).stdout)
        self.assertTrue(st[1]["tries"][0]["end"].startswith("lost"), st[1]["tries"])
        steps = [int(f) for f in read(tally).split()]
        self.assertEqual(sorted(set(steps)), list(range(1, 13)))
        recomputed = len(steps) - 12
        print(f"segments of 4 frames, node {host} killed at frame 7: {recomputed} frame(s) computed again "
              f"(steps in order: {steps})", file=sys.stderr)
        self.assertLessEqual(recomputed, 4)
        self.assertGreaterEqual(recomputed, 1)  # the step it was killed in
        for task in (3, 4):  # the renders re-simulated nothing
            self.assertEqual(json.loads(read(os.path.join(job, "profiles", f"{task:04}.json")))["nodes"]["sim"]["runs"], 0)
        # As one uninterrupted run: x(f) = v (f - 1) / fps, the exact integral, and no other file.
        self.assertEqual(files(out), [f"x_{f:02}.txt" for f in range(1, 13)])
        for f in range(1, 13):
            self.assertEqual(read(os.path.join(out, f"x_{f:02}.txt")), f"{(f - 1) * 1.0:.6f}\n")

    def test_mpi_tiles_over_three_nodes_equal_one_process(self):
        g = os.path.join(SOURCE, "graphs", "pathtrace-cornell-box.json")
        out, ref = os.path.join(self.dir, "mpi"), os.path.join(self.dir, "ref")
        env = self.mpi_env()  # `loom` below: as each node finds it on its PATH, its own install
        p = subprocess.run(["srun", "--mpi=pmix", "-N3", "-n3", "--chdir", self.dir, "loom", "run", g, "--out", out,
                            "--threads", "1", "--no-cache"], capture_output=True, text=True, timeout=180, env=env)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("tiles computed", p.stdout + p.stderr)
        loom("run", g, "--out", ref, "--threads", "1", "--no-cache", "-q")
        self.assertEqual(files(out), files(ref))
        for f in files(ref):  # bit for bit the image of one process
            self.assertEqual(read(os.path.join(out, f), "rb"), read(os.path.join(ref, f), "rb"), f)

    def test_mpi_sample_passes_dealt_over_three_nodes_take_every_sample_once(self):
        """Over TCP rank 0's counter of slots is answered only inside its own
        MPI calls: every slot must still be taken once, the counts of every
        pixel those of one process, the ranks' counts adding up to them."""
        size, spp = [64, 48], 24
        path = os.path.join(self.dir, "trace.json")
        with open(path, "w") as f:
            json.dump({"loom": 1, "seed": 3, "nodes": {
                "box": {"type": "CornellBox"},
                "trace": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}, "size": size, "spp": spp}},
                "counts": {"type": "SaveImage", "inputs": {"image": {"from": "trace.samples"}, "path": "samples.exr"}}}},
                f)
        out, ref = os.path.join(self.dir, "mpi"), os.path.join(self.dir, "ref")
        command = ["srun", "--mpi=pmix", "-N3", "-n3", "--chdir", self.dir, "loom", "run", path, "--out", out,
                   "--threads", "1", "--no-cache", "--mpi-split", "samples", "--mpi-deal", "dynamic"]
        # Without osc/pt2pt, Open MPI 4.1 cannot make the window over TCP: a message, no crash, no file.
        env = self.mpi_env()
        del env["OMPI_MCA_osc"]
        p = subprocess.run(command, capture_output=True, text=True, timeout=180, env=env)
        if p.returncode != 0:
            self.assertIn("run with OMPI_MCA_osc=sm,pt2pt set", p.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "samples.exr")))
        p = subprocess.run(command, capture_output=True, text=True, timeout=180, env=self.mpi_env())
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        taken = re.search(r"samples dealt as ranks asked in 1 pass: (\d+), (\d+), (\d+) to ranks 0\.\.2", p.stderr)
        self.assertIsNotNone(taken, p.stderr)
        self.assertEqual(sum(map(int, taken.groups())), size[0] * size[1] * spp, p.stderr)
        loom("run", path, "--out", ref, "--threads", "1", "--no-cache", "-q")
        self.assertEqual(read(os.path.join(out, "samples.exr"), "rb"), read(os.path.join(ref, "samples.exr"), "rb"))

    def mpi_env(self):
        """MPI over TCP on the bridge only (as root: allowed explicitly), with
        one-sided windows by osc/pt2pt between nodes (Open MPI 4.1's default,
        osc/rdma, cannot make a window over TCP: docs/farm.md)."""
        if not os.path.exists(os.path.join(BUILD, "lib", "libloom_mpi.so")):
            self.skipTest("loom was built without MPI")
        plugins = subprocess.run(["srun", "--mpi=list"], capture_output=True, text=True)
        if "pmix" not in plugins.stdout + plugins.stderr:
            self.skipTest("Slurm has no PMIx plugin")
        net = str(self.cluster.net)
        return dict(os.environ, OMPI_MCA_btl="tcp,self", OMPI_MCA_osc="sm,pt2pt", OMPI_MCA_btl_tcp_if_include=net,
                    OMPI_MCA_oob_tcp_if_include=net, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")

    def test_an_mpi_run_whose_node_dies_ends_with_a_clear_message_and_no_file(self):
        g = os.path.join(SOURCE, "graphs", "pathtrace-cornell-box.json")
        out = os.path.join(self.dir, "mpi")
        proc = subprocess.Popen(["srun", "--mpi=pmix", "-N3", "-n3", "--chdir", self.dir, "loom", "run", g, "--out", out,
                                 "--threads", "1", "--no-cache", "--set", "trace.spp=1024"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=self.mpi_env())

        def ranks_running():  # a `loom run` in every node
            return all(any("loom" in cmd and "run" in cmd for cmd in map(_cmdline, netns_cluster.pids_in_namespace(n.pid_ns)))
                       for n in self.cluster.nodes)
        wait_for(ranks_running, 60, "the ranks never started")
        time.sleep(2)  # tracing
        killed = time.time()
        self.cluster.kill_node(self.node("n2"))  # rank 1's
        text, _ = proc.communicate(timeout=120)
        ended = time.time() - killed
        print(f"node n2 killed under an MPI run: srun ended {ended:.1f} s later, exit {proc.returncode}", file=sys.stderr)
        self.assertNotEqual(proc.returncode, 0, text)
        self.assertIn("Node failure on n2", text)
        self.assertLess(ended, 60)
        self.assertEqual(files(out) if os.path.exists(out) else [], [])  # no partial image


def _cmdline(pid):
    try:
        return read(f"/proc/{pid}/cmdline").replace("\0", " ")
    except OSError:
        return ""


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    ran = result.testsRun - len(result.skipped)
    sys.exit(1 if not result.wasSuccessful() else 77 if ran <= 0 else 0)  # a skipped class counts as one skip, no run
