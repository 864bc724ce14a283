"""Shared fixtures: the built runner, the test node modules on the Python node
path, and a session without a disk cache."""

import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
NODES = os.path.join(HERE, "nodes")
os.environ["LOOM_PYTHON_PATH"] = NODES + ((":" + os.environ["LOOM_PYTHON_PATH"]) if os.environ.get("LOOM_PYTHON_PATH") else "")
sys.path.insert(0, NODES)

import loom  # noqa: E402


@pytest.fixture
def session():
    return loom.Session(threads=2, disk_cache=False)


@pytest.fixture
def runner():
    path = os.environ.get("LOOM_RUNNER")
    if not path or not os.path.exists(path):
        pytest.skip("LOOM_RUNNER is not set to the built loom runner")

    def run(*args, **kwargs):
        return subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=300, **kwargs)

    return run


def has_node(type):
    try:
        loom.nodes[type]
        return True
    except loom.Error:
        return False
