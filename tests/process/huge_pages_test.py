#!/usr/bin/python3
"""`loom` asks for transparent huge pages for the memory malloc gives it
(docs/architecture.md, decision 29): where the kernel gives them on request
(THP "madvise"), it executes itself again with glibc.malloc.hugetlb=1, and
glibc then madvises its large regions MADV_HUGEPAGE. Checked from outside,
by the system calls strace sees; a user's own GLIBC_TUNABLES are kept, and
one that already says hugetlb is obeyed without the second exec. The editor,
which evaluates graphs whatever its arguments, starts the same way.

Usage: huge_pages_test.py LOOM [LOOM_EDITOR]. Exit 77 (skipped, saying why) without strace
or where THP is not "madvise"."""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from strace_checks import unavailable

LOOM = sys.argv[1]
EDITOR = sys.argv[2] if len(sys.argv) > 2 else None
THP = Path("/sys/kernel/mm/transparent_hugepage/enabled")


def traced(workdir, tunables):
    """The execve and madvise calls of one `loom run` of a mesh of 1.3 M triangles
    (Eigen's matrices: malloc's memory; an image's would be on huge pages
    anyway, by Loom's own allocator, decision 27)."""
    env = dict(os.environ)
    env.pop("GLIBC_TUNABLES", None)
    if tunables is not None:
        env["GLIBC_TUNABLES"] = tunables
    trace = workdir / "trace.txt"
    run = subprocess.run(["strace", "-f", "-e", "trace=execve,madvise", "-o", str(trace), LOOM, "run",
                          str(workdir / "g.json"), "--out", str(workdir / "out"), "--no-cache", "-q"],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert (workdir / "out" / "dome.ply").exists(), "the run's file is missing"
    lines = trace.read_text().splitlines()
    execs = [l for l in lines if "execve(" in l and "= 0" in l]
    huge = [l for l in lines if "MADV_HUGEPAGE" in l]
    return execs, huge


def main():
    reason = unavailable(LOOM, "whose malloc replaces glibc's (the tunable then does nothing)")
    if reason:
        print(f"skipped: {reason}")
        return 77
    if "[madvise]" not in (THP.read_text() if THP.exists() else ""):
        print(f"skipped: transparent huge pages are not 'madvise' here ({THP}: "
              f"{THP.read_text().strip() if THP.exists() else 'absent'}), so loom does not ask for them")
        return 77
    with tempfile.TemporaryDirectory(prefix="loom-huge-pages-") as tmp:
        work = Path(tmp)
        (work / "g.json").write_text('{"loom": 1, "nodes": {'
                                     '"dome": {"type": "HemisphereMesh", "inputs": {"rings": 400, "segments": 1600}},'
                                     '"save": {"type": "SaveMesh", "inputs": {"mesh": {"from": "dome.mesh"},'
                                     ' "path": "dome.ply"}}}}')
        execs, huge = traced(work, None)
        assert len(execs) == 2 and "/proc/self/exe" in execs[1], execs
        assert huge, "no MADV_HUGEPAGE: glibc did not ask for huge pages"

        execs, huge = traced(work, "glibc.malloc.hugetlb=0")  # the user's choice: no second exec, no huge pages
        assert len(execs) == 1, execs
        assert not huge, huge[:3]

        execs, huge = traced(work, "glibc.malloc.arena_max=2")  # another tunable: kept, hugetlb added
        assert len(execs) == 2 and huge, execs

        # A command that evaluates no graph starts once.
        trace = work / "nodes.txt"
        subprocess.run(["strace", "-f", "-e", "trace=execve", "-o", str(trace), LOOM, "nodes", "Math"],
                       capture_output=True, check=True, timeout=60)
        execs = [l for l in trace.read_text().splitlines() if "execve(" in l and "= 0" in l]
        assert len(execs) == 1, execs

        if EDITOR:  # no display needed for --help
            env = {k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"}
            subprocess.run(["strace", "-f", "-e", "trace=execve", "-o", str(trace), EDITOR, "--help"],
                           capture_output=True, check=True, timeout=60, env=env)
            # Its linked libraries may start a thread before main (OpenCV's
            # OpenBLAS), so strace may split the exec's line in two.
            execs = [l for l in trace.read_text().splitlines() if "execve(" in l]
            assert len(execs) == 2 and "/proc/self/exe" in execs[1] and not any("= -1" in l for l in execs), execs
    print("ok: loom executes itself again with glibc.malloc.hugetlb=1 and glibc madvises MADV_HUGEPAGE; "
          "a user's GLIBC_TUNABLES are kept" + ("; loom-editor too" if EDITOR else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
