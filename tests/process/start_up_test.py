#!/usr/bin/python3
"""What `loom` loads and starts before a graph needs it (docs/architecture.md,
decisions 16 and 22), seen from outside by strace:

- `loom validate` of a graph that writes a PNG starts no thread: OpenBLAS,
  which OpenCV brings in, starts with one thread (OPENBLAS_NUM_THREADS=1 set
  by `loom` before any plugin loads), and a user's own OPENBLAS_NUM_THREADS=2
  is obeyed (OpenBLAS's pool then starts a thread: the test can fail);
- it opens no FFmpeg library (libavformat), which only SaveVideo needs;
- a `loom run` that writes an MP4 opens it and writes every frame;
- a Newton cloth step on one thread (`--threads 1`) starts no thread: CHOLMOD's
  OpenMP loops, whose team size was fixed when it was compiled, are bounded by
  OMP_THREAD_LIMIT=1 (set by `loom`), and a user's own OMP_THREAD_LIMIT=4 is
  obeyed (CHOLMOD's team then starts: the test can fail).

Usage: start_up_test.py LOOM. Exit 77 (skipped, saying why) without strace or
under a sanitizer."""
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from strace_checks import unavailable

LOOM = sys.argv[1]


def traced(work, args, **user):
    """The threads `loom ARGS` starts and the shared libraries it opens, with
    the environment variables in `user` set and no other OpenBLAS or OpenMP
    thread setting."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OPENBLAS_", "OMP_"))}
    env.update(user)
    trace = work / "trace.txt"
    run = subprocess.run(["strace", "-f", "-e", "trace=openat,clone,clone3", "-o", str(trace), LOOM, *args],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = trace.read_text().splitlines()
    threads = [l for l in lines if "CLONE_THREAD" in l]
    libraries = [l for l in lines if "openat(" in l and ".so" in l and "ENOENT" not in l]
    return threads, libraries


def graph(work, name, nodes, frames=1):
    path = work / name
    path.write_text(json.dumps({"loom": 1, "time": {"start": 1, "end": frames, "fps": 24}, "nodes": nodes}))
    return str(path)


def main():
    reason = unavailable(LOOM, "whose runtime starts threads of its own")
    if reason:
        print(f"skipped: {reason}")
        return 77
    with tempfile.TemporaryDirectory(prefix="loom-start-up-") as tmp:
        work = Path(tmp)
        board = {"type": "Checkerboard", "inputs": {"size": [16, 16], "cells": 2}}
        png = graph(work, "png.json", {"board": board, "save": {"type": "SaveImage", "inputs": {
            "image": {"from": "board.image"}, "path": "b.png"}}})
        threads, libraries = traced(work, ["validate", png])
        assert any("libopenblas" in l for l in libraries), "OpenBLAS is no longer loaded: this test checks nothing"
        assert not threads, f"loom validate started {len(threads)} thread(s): {threads[:2]}"
        assert not any("libavformat" in l for l in libraries), "loom validate of a PNG graph loaded FFmpeg"

        threads, _ = traced(work, ["validate", png], OPENBLAS_NUM_THREADS="2")
        assert threads, "with OPENBLAS_NUM_THREADS=2 OpenBLAS started no thread: the user's choice was not kept"

        mp4 = graph(work, "mp4.json", {"board": board, "video": {"type": "SaveVideo", "inputs": {
            "image": {"from": "board.image"}, "path": "b.mp4", "codec": "mp4v"}}}, frames=3)
        _, libraries = traced(work, ["run", mp4, "--out", str(work / "out"), "--no-cache", "-q"])
        assert any("libloom_video_files.so" in l for l in libraries), "SaveVideo did not open its library"
        assert any("libavformat" in l for l in libraries), "SaveVideo did not load FFmpeg"
        assert (work / "out" / "b.mp4").stat().st_size > 0, "no MP4 written"

        # 60² vertices, two frames: from the second the cloth moves, and
        # CHOLMOD's factorization runs loops large enough for its team.
        cloth = graph(work, "cloth.json", {
            "grid": {"type": "MassSpringGrid", "inputs": {"vertices": [60, 60]}},
            "step": {"type": "ClothStep", "inputs": {"state": {"from": "grid.state"}, "solver": "newton",
                                                     "iterations": 2}},
            "save": {"type": "SaveMesh", "inputs": {"mesh": {"from": "step.mesh"}, "path": "c{frame}.obj"}}},
            frames=2)
        args = ["run", cloth, "--out", str(work / "cloth"), "--no-cache", "-q", "--threads", "1"]
        threads, _ = traced(work, args)
        assert not threads, f"a Newton cloth step on one thread started {len(threads)} thread(s): {threads[:2]}"
        threads, _ = traced(work, args, OMP_THREAD_LIMIT="4")
        assert threads, "with OMP_THREAD_LIMIT=4 CHOLMOD started no thread: the user's choice was not kept"
    print("ok: a PNG graph validates with no thread started and no FFmpeg loaded; "
          "OPENBLAS_NUM_THREADS=2 is obeyed; SaveVideo loads FFmpeg when it writes; "
          "a Newton cloth step starts no OpenMP thread, and OMP_THREAD_LIMIT=4 is obeyed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
