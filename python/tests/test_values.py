"""Values between the engine and NumPy: equal to the runner's, bit-exact
round trips, meshes, JSON, and clear errors for what an input cannot take."""

import json
import os
import shutil

import numpy as np
import pytest

import loom
from conftest import has_node

REPO = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))


def test_image_equals_runner_output(session, runner, tmp_path):
    # Reference: the same graph run by `loom run`, written as a float EXR and
    # read back by LoadImage (no Python conversion on that path). HeightMap is
    # linear, so the EXR holds its values unconverted.
    if not has_node("HeightMap"):
        pytest.skip("plugin shading not built")
    g = loom.Graph()
    board = g.add("HeightMap", size=[96, 64], pattern="bumps")
    warp = g.add("ImageWarp", image=board.image, method="rbf", pairs=[[10, 10, 20, 14], [80, 50, 70, 40]])
    g.add("SaveImage", image=warp.image, path="warp.exr", depth="float")
    g.save(tmp_path / "g.json")
    r = runner("run", tmp_path / "g.json", "--out", tmp_path / "out", "--no-cache")
    assert r.returncode == 0, r.stderr
    mine = session.run(g, warp.image)
    ref = loom.Graph()
    load = ref.add("LoadImage", path=str(tmp_path / "out" / "warp.exr"), decode="keep")
    theirs = session.run(ref, load.image)
    assert mine.shape == (64, 96, 1) and mine.encoding == "linear" and mine.dtype == np.float32
    assert np.array_equal(np.asarray(mine), np.asarray(theirs))


def test_numpy_image_round_trips_bit_exactly(session):
    rng = np.random.default_rng(7)
    a = rng.standard_normal((33, 47, 4)).astype(np.float32) * np.float32(1e3)
    a[0, 0] = [np.float32(1e-42), -0.0, np.finfo(np.float32).max, np.finfo(np.float32).tiny]  # subnormal, -0, extremes
    g = loom.Graph()
    s = g.add("Switch", index=0, in0=a)  # a C++ node passes it through
    out = session.run(g, s.value)
    assert out.shape == a.shape
    assert np.array_equal(np.asarray(out).view(np.uint32), a.view(np.uint32))
    gray = session.run(g, s.value, set={"switch.in0": a[:, :, 0]})
    assert gray.shape == (33, 47, 1) and np.array_equal(np.asarray(gray)[:, :, 0].view(np.uint32), a[:, :, 0].view(np.uint32))


def test_image_is_a_view_kept_alive_by_the_array(session):
    g = loom.Graph()
    board = g.add("Checkerboard", size=[64, 32], cells=4)
    img = session.run(g, board.image)
    assert img.encoding == "srgb" and not img.flags.writeable and not img.flags.owndata
    session.clear_cache()
    del g
    expected_corner = np.array([0.95, 0.95, 0.95], dtype=np.float32)  # color_a's default
    assert np.allclose(img[0, 0], expected_corner)  # still readable: the array holds the pixels


def test_mesh_arrays_and_numpy_mesh_as_input(session):
    if not has_node("GridMesh"):
        pytest.skip("plugin generate not built")
    g = loom.Graph()
    grid = g.add("GridMesh")
    mesh = session.run(g, grid.mesh)
    assert mesh.vertices.ndim == 2 and mesh.vertices.shape[1] == 3 and mesh.faces.shape[1] == 3
    assert mesh.faces.dtype == np.int32 and mesh.faces.max() < len(mesh.vertices)
    # A mesh made in NumPy goes into a C++ node and comes back unchanged.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    tet = loom.Mesh(v, f)
    s = g.add("Switch", in0=tet)
    back = session.run(g, s.value)
    assert np.array_equal(back.vertices, v) and np.array_equal(back.faces, f) and back.uv is None


def test_json_and_lists(session):
    g = loom.Graph()
    board = g.add("Checkerboard", size=[32, 16], cells=2)
    stats = g.add("py.loomtest_nodes.Stats", image=board.image)
    r = session.run(g, [stats.mean, stats.size])
    assert r[stats.size] == [32, 16]
    ref = np.asarray(session.run(g, board.image)).reshape(-1, 3).mean(axis=0)
    assert np.allclose(r[stats.mean], ref, rtol=0, atol=1e-6)


@pytest.mark.parametrize("bad, message", [
    (np.zeros((8, 8, 3), dtype=np.uint8), "float32"),
    (np.zeros((8, 8, 3), dtype=np.complex64), "float32"),
    (np.zeros((8, 8, 5), dtype=np.float32), "channels"),
    (np.zeros((2, 8, 8, 3), dtype=np.float32), "dimensions"),
    (np.full((8, 8, 3), np.nan, dtype=np.float32), "NaN"),
    ("a string", "expected"),
])
def test_bad_image_input_is_a_clear_error(bad, message):
    if not has_node("SaveImage"):
        pytest.skip("plugin io not built")
    g = loom.Graph()
    with pytest.raises(loom.InputError) as e:
        g.add("SaveImage", id="save", image=bad, path="x.png")
    assert e.value.pointer == "/nodes/save/inputs/image"
    assert message.lower() in str(e.value).lower()
    assert "save" not in g  # nothing half-added


def test_bad_literal_inputs():
    g = loom.Graph()
    with pytest.raises(loom.InputError, match="finite"):
        g.add("Checkerboard", size=[8, 8], cells=float("nan"))
    with pytest.raises(loom.InputError, match="did you mean"):
        g.add("Checkerboard", cels=3)
    with pytest.raises(loom.Error, match="did you mean \"Checkerboard\""):
        g.add("CheckerBord")
    # A value out of the declared range is refused when given, as in a graph file.
    with pytest.raises(loom.InputError, match="out of range: expected between 1 and 4096"):
        g.add("Checkerboard", cells=0)
    with pytest.raises(loom.InputError, match="out of range"):
        g.add("Checkerboard", size=[0, 8])


def test_load_and_save_give_the_runner_and_editor_files(tmp_path):
    shutil.copytree(os.path.join(REPO, "graphs", "groups"), tmp_path / "groups")  # what groups-file.json uses
    for name in sorted(n for n in os.listdir(os.path.join(REPO, "graphs")) if n.endswith(".json")):
        path = os.path.join(REPO, "graphs", name)
        g = loom.load(path)
        g.save(tmp_path / name)
        with open(path) as f:
            original = json.load(f)
        with open(tmp_path / name) as f:
            text = f.read()
        assert json.loads(text) == original, name
        loom.load(tmp_path / name).save(tmp_path / ("again-" + name))
        assert (tmp_path / ("again-" + name)).read_text() == text, name  # a fixed point


def test_graph_errors_carry_the_pointer(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"loom": 1, "nodes": {"a": {"type": "Checkerboard", "inputs": {"cells": "many"}}}}')
    g = loom.load(bad)
    with pytest.raises(loom.GraphError) as e:
        loom.Session(disk_cache=False).run(g)
    assert e.value.pointer == "/nodes/a/inputs/cells" and e.value.node == "a"
