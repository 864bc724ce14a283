"""The third hostile probe's defects (issue 37), each a regression test of
the real runner: job folders (edited manifests, links, folders that are not
Loom's, recorded pids, two dispatchers at once), sweep and frame limits,
group limits and messages, --watch on a FIFO. Usage: reliability_test.py
LOOM SOURCE_DIR TEST_PLUGIN_DIR [unittest arguments]."""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

LOOM, SOURCE, TEST_PLUGINS = map(os.path.abspath, sys.argv[1:4])
del sys.argv[1:4]
os.environ["LOOM_PLUGIN_PATH"] = TEST_PLUGINS  # Sleep, WriteText, FrameNumber, Fail


def loom(*args, env=None, timeout=120, cwd=None):
    return subprocess.run([LOOM, *map(str, args)], capture_output=True, text=True, timeout=timeout,
                          env=dict(os.environ, **(env or {})), cwd=cwd)


def write_json(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def read(path):
    with open(path) as f:
        return f.read()


def frames_graph(folder, ms, last=4):
    return write_json(os.path.join(folder, "graph.json"), {"loom": 1, "time": {"start": 1, "end": last, "fps": 24}, "nodes": {
        "f": {"type": "FrameNumber"},
        "s": {"type": "Sleep", "inputs": {"value": {"from": "f.value"}, "ms": ms}},
        "w": {"type": "WriteText", "inputs": {"value": {"from": "s.value"}, "path": "f_{frame:02}.txt"}}}})


def status(job, task):
    return json.loads(read(os.path.join(job, "status", f"{task:04}.json")))


def task_run_pid(job, timeout=30):
    """The pid of a `loom run` started by a task of `job`: the child of the
    process a running task's status names (`loom jobs task`, or the local
    dispatcher's fork of itself, whose command line is the dispatcher's)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        for name in sorted(os.listdir(os.path.join(job, "status"))) if os.path.isdir(os.path.join(job, "status")) else []:
            try:
                st = json.loads(read(os.path.join(job, "status", name)))
                children = read(f"/proc/{st['pid']}/task/{st['pid']}/children").split()
            except (OSError, ValueError, KeyError):
                continue
            if st.get("state") == "running" and children:
                return int(children[0])
        time.sleep(0.02)
    raise TimeoutError("no task started")


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


class JobFolderTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-jobs37-")
        self.out = os.path.join(self.dir, "out")
        self.job = os.path.join(self.out, ".loom-job")
        self.procs = []

    def tearDown(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
        shutil.rmtree(self.dir, ignore_errors=True)

    def dry_run(self, ms=1, last=4, chunk=2):
        g = frames_graph(self.dir, ms, last)
        p = loom("submit", g, "--to", "local", "--out", self.out, "--chunk", chunk, "--no-cache", "--dry-run")
        self.assertEqual(p.returncode, 0, p.stderr)
        return g

    def edit_manifest(self, edit):
        path = os.path.join(self.job, "manifest.json")
        doc = json.loads(read(path))
        edit(doc)
        write_json(path, doc)

    def background(self, *args):
        p = subprocess.Popen([LOOM, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.procs.append(p)
        return p

    # item 1 and 2: an edited manifest is refused, naming what is wrong; never an abort or a silent exit 0
    def test_an_edited_manifest_is_refused_naming_the_task(self):
        self.dry_run()
        cases = [
            (lambda d: d["tasks"][1].update(id=7), "/tasks/1/id"),
            (lambda d: d["tasks"][0].update(id=-1), "/tasks/0/id"),
            (lambda d: d["tasks"][1].update(id=0), "/tasks/1/id"),  # a duplicate
            (lambda d: d["tasks"][0].update(stage=9), "/tasks/0/stage"),
            (lambda d: d.update(jobs=0), "/jobs"),
            (lambda d: d.update(jobs=-4), "/jobs"),
            (lambda d: d["tasks"][0].update(args=[1, 2]), "/tasks/0/args/0: task 0 (frames 1-2)"),
        ]
        original = read(os.path.join(self.job, "manifest.json"))
        for edit, expected in cases:
            with open(os.path.join(self.job, "manifest.json"), "w") as f:
                f.write(original)
            self.edit_manifest(edit)
            for action in (["resume"], ["task", "0"], ["status"]):
                p = loom("jobs", action[0], self.job, *action[1:])
                self.assertEqual(p.returncode, 2, (expected, action, p.stderr))
                self.assertIn(expected, p.stderr)
                self.assertNotIn("json.exception", p.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "f_01.txt")))  # nothing ran

    # item 1: a job folder that cannot be written is an error, not SIGABRT
    def test_a_job_folder_that_cannot_be_written_is_an_error_not_an_abort(self):
        self.dry_run()
        os.makedirs(os.path.join(self.job, "status", "0000.json", "x"))  # the status cannot be replaced
        p = loom("jobs", "task", self.job, "0")
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("error: ", p.stderr)
        self.assertIn("0000.json", p.stderr)
        os.makedirs(os.path.join(self.job, "local.pid", "x"))  # nor the dispatcher's pid
        p = loom("jobs", "resume", self.job)
        self.assertIn(p.returncode, (1, 2), p.stderr)
        self.assertIn("local.pid", p.stderr)

    # item 3: task logs never follow a symbolic link out of the job folder
    def test_task_logs_never_follow_a_link_out_of_the_job_folder(self):
        self.dry_run()
        outside = os.path.join(self.dir, "outside.txt")
        write_json(outside, "keep")
        os.symlink(outside, os.path.join(self.job, "logs", "task-0000.log"))
        p = loom("jobs", "resume", self.job, "-j", "1")
        self.assertEqual(read(outside), '"keep"')
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertEqual(status(self.job, 0)["state"], "failed")
        self.assertIn("symbolic link", status(self.job, 0)["message"])
        self.assertEqual(status(self.job, 1)["state"], "done")  # the other task was not stopped by it

        shutil.rmtree(os.path.join(self.job, "logs"))
        elsewhere = os.path.join(self.dir, "elsewhere")
        os.makedirs(elsewhere)
        os.symlink(elsewhere, os.path.join(self.job, "logs"))
        p = loom("jobs", "resume", self.job)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("is a symbolic link", p.stderr)
        self.assertEqual(os.listdir(elsewhere), [])

    # item 6: a deleted logs folder is made again, not "see a log that does not exist"
    def test_a_deleted_logs_folder_is_made_again(self):
        self.dry_run()
        shutil.rmtree(os.path.join(self.job, "logs"))
        p = loom("jobs", "resume", self.job)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual([status(self.job, i)["state"] for i in (0, 1)], ["done", "done"])
        self.assertIn("attempt 1", read(os.path.join(self.job, "logs", "task-0000.log")))

    # item 2: a task whose output was deleted after it ended is run again
    def test_resume_runs_again_a_done_task_whose_output_is_gone(self):
        self.dry_run()
        self.assertEqual(loom("jobs", "resume", self.job).returncode, 0)
        os.remove(os.path.join(self.out, "f_03.txt"))
        before = os.path.getmtime(os.path.join(self.job, "status", "0000.json"))
        p = loom("jobs", "resume", self.job)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("task 1 (frames 3-4) is done but", p.stderr)
        self.assertIn("resuming 1 of 2 tasks", p.stderr)
        self.assertEqual(read(os.path.join(self.out, "f_03.txt")), "3.000000\n")
        self.assertEqual(os.path.getmtime(os.path.join(self.job, "status", "0000.json")), before)
        self.assertIn("every task of", loom("jobs", "resume", self.job).stderr)

    # item 4: a folder that is not a job folder is never cleared or overwritten
    def test_job_dir_on_an_ordinary_folder_is_refused_and_left_alone(self):
        g = frames_graph(self.dir, 1)
        proj = os.path.join(self.dir, "proj")
        for sub in ("logs", "status", "profiles", "slurm"):
            os.makedirs(os.path.join(proj, sub))
            write_json(os.path.join(proj, sub, "mine.json"), sub)
        write_json(os.path.join(proj, "graph.json"), {"mine": True})
        before = {root: sorted(files) for root, _, files in os.walk(proj)}
        for job_dir, cwd in ((proj, None), (".", proj)):
            p = loom("submit", g, "--to", "local", "--out", self.out, "--job-dir", job_dir, "--dry-run", cwd=cwd)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("not a Loom job folder", p.stderr)
            self.assertEqual({root: sorted(files) for root, _, files in os.walk(proj)}, before)
            self.assertEqual(json.loads(read(os.path.join(proj, "graph.json"))), {"mine": True})
        # A job folder made by submit is still replaced by the next submit.
        self.assertEqual(loom("submit", g, "--to", "local", "--out", self.out, "--dry-run").returncode, 0)
        p = loom("submit", g, "--to", "local", "--out", self.out, "--dry-run", "--chunk", "1")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(len(json.loads(read(os.path.join(self.job, "manifest.json")))["tasks"]), 4)

    # item 5: two resumes at once do not run a task twice
    def test_two_resumes_at_once_run_each_task_once(self):
        self.dry_run(ms=700)
        both = [self.background("jobs", "resume", self.job, "-j", "2") for _ in range(2)]
        errors = [p.communicate(timeout=120)[1] for p in both]
        self.assertEqual(sorted(p.returncode for p in both), [0, 2], errors)
        refused = errors[[p.returncode for p in both].index(2)]
        self.assertTrue("another loom" in refused or "is running" in refused, refused)
        for i in (0, 1):
            self.assertEqual(read(os.path.join(self.job, "logs", f"task-{i:04}.log")).count("== frames"), 1)
            self.assertEqual(status(self.job, i)["attempts"], 1)
        self.assertEqual(read(os.path.join(self.out, "f_04.txt")), "4.000000\n")

    # item 5: after the dispatcher is SIGKILLed, its tasks still hold the job and cancel reaches them
    def test_cancel_reaches_the_tasks_of_a_killed_dispatcher(self):
        self.dry_run(ms=30000, last=1, chunk=1)
        dispatcher = self.background("jobs", "resume", self.job)
        run = task_run_pid(self.job)
        time.sleep(0.3)
        dispatcher.kill()
        dispatcher.wait()
        p = loom("jobs", "resume", self.job)
        self.assertEqual(p.returncode, 2, p.stderr)  # the task still runs: not started twice
        start = time.time()
        p = loom("jobs", "cancel", self.job)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("sent SIGTERM to task 0", p.stderr)
        while alive(run) and time.time() - start < 15:
            time.sleep(0.05)
        self.assertFalse(alive(run), "the task's loom run kept running")
        deadline = time.time() + 10
        while status(self.job, 0)["state"] == "running" and time.time() < deadline:
            time.sleep(0.05)
        self.assertEqual(status(self.job, 0)["state"], "cancelled")

    # item 5: a recorded pid is used only while it names the process that recorded it
    def test_recorded_pids_of_other_processes_are_neither_signalled_nor_waited_for(self):
        self.dry_run()
        stranger = subprocess.Popen(["sleep", "60"])
        self.procs.append(stranger)
        for content in (f"{stranger.pid} 12345\n", f"{stranger.pid}\n"):  # a stale file: new and old format
            with open(os.path.join(self.job, "local.pid"), "w") as f:
                f.write(content)
            p = loom("jobs", "cancel", self.job)
            self.assertEqual(p.returncode, 0, p.stderr)
            time.sleep(0.2)
            self.assertIsNone(stranger.poll(), "an unrelated process got SIGTERM")
            self.assertIn("not signalled", p.stderr)
        os.remove(os.path.join(self.job, "local.pid"))
        host = os.uname().nodename
        write_json(os.path.join(self.job, "status", "0000.json"),
                   {"state": "running", "host": host, "pid": stranger.pid, "pid_start": 12345})
        write_json(os.path.join(self.job, "status", "0001.json"), {"state": "running", "host": host, "pid": stranger.pid})
        p = loom("jobs", "resume", self.job)  # the reused pid does not block it
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("resuming 2 of 2 tasks", p.stderr)
        self.assertIsNone(stranger.poll())


class SweepLimitTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-sweep37-")
        self.g = write_json(os.path.join(self.dir, "g.json"), {"loom": 1, "nodes": {
            "a": {"type": "Sleep", "inputs": {"value": 1, "ms": 0}},
            "b": {"type": "Sleep", "inputs": {"value": {"from": "a.value"}, "ms": 0}},
            "w": {"type": "WriteText", "inputs": {"value": {"from": "b.value"}, "path": "v.txt"}}}})
        self.out = os.path.join(self.dir, "out")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    # item 7: the points are counted, without overflow, before any graph is built
    def test_a_grid_past_the_limit_is_refused_before_anything_is_built(self):
        start = time.time()
        p = loom("run", self.g, "--out", self.out, "--sweep", "a.value=0:1:1000", "--sweep", "b.ms=0:1:1000")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("1000 × 1000 = 1000000 points is more than the limit of 100000", p.stderr)
        self.assertIn("LOOM_MAX_SWEEP_POINTS", p.stderr)
        self.assertLess(time.time() - start, 20)
        p = loom("run", self.g, "--out", self.out, *sum((["--sweep", f"{x}=0:1:65536"] for x in
                                                          ("a.value", "a.ms", "b.value", "b.ms")), []))
        self.assertEqual(p.returncode, 2, p.stderr)  # the count wrapped to 0: "0 points", exit 0
        self.assertIn("more than the limit", p.stderr)
        p = loom("submit", self.g, "--to", "local", "--out", self.out, "--dry-run", "--sweep", "a.value=0:1:1000",
                 "--sweep", "b.ms=0:1:1000")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertFalse(os.path.exists(self.out))
        env = {"LOOM_MAX_SWEEP_POINTS": "4"}
        p = loom("run", self.g, "--out", self.out, "-q", "--sweep", "a.value=1,2,3", "--sweep", "b.ms=0,1", env=env)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("3 × 2 = 6 points is more than the limit of 4", p.stderr)
        p = loom("run", self.g, "--out", self.out, "-q", "--sweep", "a.value=1,2", "--sweep", "b.ms=0,1", env=env)
        self.assertEqual(p.returncode, 0, p.stderr)

    # item 8: the same input swept twice is refused
    def test_the_same_input_swept_twice_is_refused(self):
        p = loom("run", self.g, "--out", self.out, "--sweep", "a.value=1,2", "--sweep", "a.value=3,4")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("a.value is swept twice", p.stderr)

    # item 9: ranges say what is wrong with them
    def test_ranges_near_the_limits_of_numbers(self):
        p = loom("run", self.g, "--out", self.out, "-q", "--sweep", "a.value=-1e308:1e308:3", "--record", "a.value")
        self.assertEqual(p.returncode, 0, p.stderr)
        values = [pt["records"]["a.value"] for pt in json.loads(read(os.path.join(self.out, "sweep.json")))["points"]]
        self.assertEqual(values, [-1e308, 0.0, 1e308])
        p = loom("run", self.g, "--out", self.out, "--sweep", "a.ms=0:1e300:3")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("is beyond what an Int input holds", p.stderr)
        self.assertNotIn("-9223372036854775808", p.stderr)
        p = loom("run", self.g, "--out", self.out, "--set", "a.ms=3000000000")
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("3000000000 (an integer) is beyond what an Int holds", p.stderr)

    # item 9: with -q a failing point still says why
    def test_a_failing_point_says_why_also_when_quiet(self):
        g = write_json(os.path.join(self.dir, "f.json"), {"loom": 1, "nodes": {
            "ok": {"type": "Sleep", "inputs": {"value": 4, "ms": 1}},
            "bad": {"type": "Fail"},
            "pick": {"type": "Switch", "inputs": {"in0": {"from": "ok.value"}, "in1": {"from": "bad.value"}}},
            "w": {"type": "WriteText", "inputs": {"value": {"from": "pick.value"}, "path": "v.txt"}}}})
        p = loom("run", g, "--out", self.out, "-q", "--no-cache", "--sweep", "pick.index=1,0")
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn('error: point 0 ({"pick.index":1}): node "bad" failed', p.stderr)
        self.assertNotIn("error: point 1", p.stderr)


class FrameLimitTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-frames37-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    # still open from round 2: a time range of 1..1e9 ran for 100 minutes without a word
    def test_a_range_past_the_frame_limit_is_refused_naming_it(self):
        g = frames_graph(self.dir, 0, last=1000000000)
        out = os.path.join(self.dir, "out")
        for args in ([], ["--sweep", "s.ms=0,1"]):
            p = loom("run", g, "--out", out, "--no-cache", *args, timeout=60)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("1-1000000000 is 1000000000 frames, more than the limit of 1000000", p.stderr)
            self.assertIn("LOOM_MAX_FRAMES", p.stderr)
        p = loom("submit", g, "--to", "local", "--out", out, "--dry-run", timeout=60)
        self.assertEqual(p.returncode, 2, p.stderr)
        p = loom("run", g, "--out", out, "--no-cache", "--frames", "1-5", env={"LOOM_MAX_FRAMES": "4"})
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("--frames 1-5 is 5 frames, more than the limit of 4", p.stderr)
        p = loom("run", g, "--out", out, "--no-cache", "-q", "--frames", "1-4", env={"LOOM_MAX_FRAMES": "4"})
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(read(os.path.join(out, "f_04.txt")), "4.000000\n")


class GroupLimitTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-groups37-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def graph(self, doc, name="g.json"):
        return write_json(os.path.join(self.dir, name), doc)

    def validate(self, doc, timeout=60, env=None):
        return loom("validate", self.graph(doc), timeout=timeout, env=env)

    # item 10: nesting and copies are counted before they are made
    def test_deep_and_wide_groups_are_refused_before_they_exhaust_memory(self):
        for depth in (1000, 10000):
            groups = {f"G{k}": {"nodes": {"n": {"type": f"G{k + 1}"}}} for k in range(depth)}
            groups[f"G{depth}"] = {"nodes": {"m": {"type": "Sleep"}}}
            start = time.time()
            p = self.validate({"loom": 2, "groups": groups, "nodes": {"top": {"type": "G0"}}})
            self.assertEqual(p.returncode, 2, p.stderr[-500:])  # 10,000 levels: SIGSEGV
            self.assertIn("groups nest more than 64 levels deep", p.stderr)
            self.assertLess(time.time() - start, 30)
        groups = {f"G{k}": {"nodes": {"a": {"type": f"G{k + 1}"}, "b": {"type": f"G{k + 1}"}}} for k in range(22)}
        groups["G22"] = {"nodes": {"m": {"type": "Sleep"}}}
        fan = {"loom": 2, "groups": groups, "nodes": {"top": {"type": "G0"}}}
        p = self.validate(fan)
        self.assertEqual(p.returncode, 2, p.stderr[-500:])
        self.assertIn("more than 100000 nodes, the limit", p.stderr)
        self.assertIn("LOOM_MAX_GROUP_NODES", p.stderr)
        self.assertEqual(p.stderr.count("more than 100000 nodes"), 1)  # reported once, nothing more expanded
        # 3 levels of 2: 59 nodes and instances made over every level's body.
        groups = {k: v for k, v in groups.items() if int(k[1:]) >= 19}
        small = {"loom": 2, "groups": groups, "nodes": {"top": {"type": "G19"}}}
        self.assertEqual(self.validate(small, env={"LOOM_MAX_GROUP_NODES": "59"}).returncode, 0)
        self.assertEqual(self.validate(small, env={"LOOM_MAX_GROUP_NODES": "58"}).returncode, 2)

    def test_a_huge_group_file_is_not_read(self):
        big = os.path.join(self.dir, "big.json")
        with open(big, "w") as f:
            f.truncate(1536 << 20)  # sparse: 1.5 GB of nothing
        start = time.time()
        p = self.validate({"loom": 2, "nodes": {"x": {"type": "big.json"}}})
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("is 1536 MiB, more than the 64 MiB a group file may hold", p.stderr)
        self.assertLess(time.time() - start, 10)

    # item 12: what stands where a group file should be is named
    def test_a_group_file_that_is_not_a_file_is_named_as_such(self):
        os.mkdir(os.path.join(self.dir, "dir.json"))
        os.mkfifo(os.path.join(self.dir, "fifo.json"))
        os.symlink("/dev/zero", os.path.join(self.dir, "zero.json"))
        for name, kind in (("dir.json", "a directory"), ("fifo.json", "a FIFO"), ("zero.json", "a character device")):
            p = self.validate({"loom": 2, "nodes": {"x": {"type": name}}}, timeout=20)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn(f'group file "{name}" is {kind}', p.stderr)

    # item 11: docs/graph-format.md: a name that is both a group and a plugin's node type is an error
    def test_an_inline_group_named_like_a_node_type_is_an_error(self):
        p = self.validate({"loom": 2, "groups": {"Posterize": {"nodes": {"s": {"type": "Sleep"}}}},
                           "nodes": {"p": {"type": "Posterize"}}})
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn('"Posterize" names both a group and a node type', p.stderr)

    # item 12: interface mistakes are reported once, where they are written, with a suggestion
    def test_interface_mistakes_are_reported_once_where_written(self):
        group = {"inputs": {"x": {"type": "Float", "default": 1, "to": ["s.value"]},
                            "y": {"type": "Float", "default": 2, "to": ["s.value"]}},
                 "outputs": {"v": {"from": "s.value"}}, "nodes": {"s": {"type": "Sleep"}}}
        p = self.validate({"loom": 2, "groups": {"G": group}, "nodes": {"a": {"type": "G"}}})
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn('interface inputs "x" and "y" both feed s.value', p.stderr)
        self.assertNotIn("leave it unset", p.stderr)
        group = {"inputs": {"t": {"type": "Int", "default": 1, "to": ["s.mss"]}},
                 "outputs": {"v": {"from": "s.value"}}, "nodes": {"s": {"type": "Sleep"}}}
        p = self.validate({"loom": 2, "groups": {"G": group}, "nodes": {"a": {"type": "G"}, "b": {"type": "G"}}})
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertEqual(p.stderr.count('has no input "mss"'), 1, p.stderr)
        self.assertIn('/groups/G/inputs/t/to/0: interface input "t" feeds s.mss, but node "s" has no input "mss": '
                      'did you mean "ms"?', p.stderr)


    # item 12: a Float reaching Repeat's count (through Switch's Any output) names the input
    def test_a_value_of_the_wrong_type_through_an_any_output_names_the_input(self):
        body = {"inputs": {"x": {"type": "Float", "default": 0, "to": ["h.value"]}},
                "outputs": {"x": {"from": "h.value"}}, "nodes": {"h": {"type": "Sleep", "inputs": {"ms": 0}}}}
        g = self.graph({"loom": 2, "groups": {"Halve": body}, "nodes": {
            "a": {"type": "Sleep", "inputs": {"value": 2.5, "ms": 0}},
            "sw": {"type": "Switch", "inputs": {"in0": {"from": "a.value"}}},
            "loop": {"type": "Repeat", "body": "Halve", "inputs": {"count": {"from": "sw.value"}, "x": 1}},
            "w": {"type": "WriteText", "inputs": {"value": {"from": "loop.x"}, "path": "x.txt"}}}})
        p = loom("run", g, "--out", os.path.join(self.dir, "o"), "--no-cache")
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn('node "loop" (Repeat) failed: input "count": a Float value arrived', p.stderr)


class SignalTest(unittest.TestCase):
    # still open from round 2: SIGTERM during a run exited 130 with no error line
    def test_a_stop_signal_ends_the_run_with_an_error_line_naming_it(self):
        d = tempfile.mkdtemp(prefix="loom-signal37-")
        try:
            g = write_json(os.path.join(d, "g.json"), {"loom": 1, "nodes": {
                "s": {"type": "Sleep", "inputs": {"value": 1, "ms": 20000}},
                "w": {"type": "WriteText", "inputs": {"value": {"from": "s.value"}, "path": "v.txt"}}}})
            p = subprocess.Popen([LOOM, "run", g, "--out", os.path.join(d, "o"), "--no-cache"],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            deadline = time.time() + 30
            while time.time() < deadline:  # until the run catches SIGTERM (SigCgt bit 15)
                caught = [l for l in read(f"/proc/{p.pid}/status").splitlines() if l.startswith("SigCgt:")]
                if caught and int(caught[0].split()[1], 16) & (1 << (signal.SIGTERM - 1)):
                    break
                time.sleep(0.02)
            p.send_signal(signal.SIGTERM)
            _, err = p.communicate(timeout=30)
            self.assertEqual(p.returncode, 130, err)
            self.assertIn("error: interrupted by SIGTERM: the nodes still running were cancelled", err)
            self.assertFalse(os.path.exists(os.path.join(d, "o", "v.txt")))
        finally:
            shutil.rmtree(d, ignore_errors=True)


class WatchTest(unittest.TestCase):
    # item 16: a FIFO given as the graph blocked before Ctrl-C was handled
    def test_a_fifo_as_the_graph_is_refused_at_once(self):
        d = tempfile.mkdtemp(prefix="loom-watch37-")
        try:
            os.mkfifo(os.path.join(d, "g.json"))
            p = subprocess.Popen([LOOM, "run", os.path.join(d, "g.json"), "--watch", "--out", os.path.join(d, "o")],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            try:
                _, err = p.communicate(timeout=5)
            except subprocess.TimeoutExpired:
                p.send_signal(signal.SIGINT)
                try:
                    p.communicate(timeout=2)
                finally:
                    p.kill()
                self.fail("--watch blocked on the FIFO")
            self.assertEqual(p.returncode, 2, err)
            self.assertIn("is a FIFO", err)
        finally:
            shutil.rmtree(d, ignore_errors=True)


MPIEXEC = shutil.which("mpiexec")
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
MPI_ARGS = ["--oversubscribe", "--bind-to", "none", "--mca", "btl", "self,vader", "--mca", "oob_tcp_if_include", "lo",
            "--mca", "btl_vader_single_copy_mechanism", "none"]


@unittest.skipUnless(MPIEXEC and os.path.exists(os.path.join(os.path.dirname(os.path.dirname(LOOM)), "lib",
                                                             "libloom_mpi.so")), "no mpiexec or libloom_mpi")
class MpiLeftoversTest(unittest.TestCase):
    """Item 15: .loom-mpi-cache left in --out; ranks given --out folders of their own."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="loom-mpi37-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def test_ranks_with_an_out_of_their_own_are_refused(self):
        g = frames_graph(self.dir, 1)
        a, b = os.path.join(self.dir, "a"), os.path.join(self.dir, "b")
        cmd = [MPIEXEC, *MPI_ARGS, "-n", "1", LOOM, "run", g, "--out", a, "--no-cache", ":",
               "-n", "1", LOOM, "run", g, "--out", b, "--no-cache"]
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=240, env=MPI_ENV)
        self.assertNotEqual(p.returncode, 0, p.stderr)
        self.assertIn("is not one folder on every rank", p.stderr)

    def test_sigterm_to_every_rank_leaves_no_mpi_cache(self):
        g = write_json(os.path.join(self.dir, "g.json"), {"loom": 1, "time": {"start": 1, "end": 40, "fps": 24},
            "nodes": {"sim": {"type": "Integrate", "inputs": {"x": 0, "v": 24, "ms": 100}},
                      "w": {"type": "WriteText", "inputs": {"value": {"from": "sim.x"}, "path": "x_{frame:02}.txt"}}}})
        out = os.path.join(self.dir, "out")
        run = subprocess.Popen([MPIEXEC, "-n", "2", *MPI_ARGS, LOOM, "run", g, "--out", out, "--no-cache"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=MPI_ENV)
        store = os.path.join(out, ".loom-mpi-cache")
        deadline = time.time() + 60
        while not os.path.isdir(store) and time.time() < deadline:
            time.sleep(0.05)
        self.assertTrue(os.path.isdir(store))
        time.sleep(0.5)  # rank 0 simulating, rank 1 waiting
        # This test's ranks only: every `loom run` of the binary would also
        # stop the suite's other tests running beside it (the example graphs'
        # runs failed "interrupted by SIGTERM" now and then).
        ranks = [int(e) for e in filter(str.isdigit, os.listdir("/proc"))
                 if read_quiet(f"/proc/{e}/cmdline").split("\0")[:3] == [LOOM, "run", g]]
        for pid in ranks:
            os.kill(pid, signal.SIGTERM)
        _, err = run.communicate(timeout=60)
        self.assertNotEqual(run.returncode, 0)
        self.assertFalse(os.path.exists(store), err)


def read_quiet(path):
    try:
        return read(path)
    except OSError:
        return ""


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
