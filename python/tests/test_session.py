"""Sessions and Python nodes: caching, the same result in a Session, in
`loom run` and beside C++ nodes in parallel, errors, Ctrl-C, the GIL."""

import _thread
import os
import threading
import time

import numpy as np
import pytest

import loom


def scaled_board_graph(factor=3.0):
    g = loom.Graph()
    board = g.add("Checkerboard", id="board", size=[40, 30], cells=5)
    scale = g.add("py.loomtest_nodes.Scale", id="scale", image=board.image, factor=factor)
    return g, board, scale


def test_python_node_matches_numpy(session):
    g, board, scale = scaled_board_graph(3.0)
    r = session.run(g, [board.image, scale.image])
    assert np.array_equal(np.asarray(r[scale.image]), np.asarray(r[board.image]) * np.float32(3.0))
    assert r[scale.image].encoding == "srgb"


def test_threads_is_a_whole_number_of_at_least_zero():
    # As `loom run --threads`: refused with the same words, not truncated or
    # read as "all cores".
    for bad in (-1, 1.5, "2", True, None):
        with pytest.raises(ValueError, match=r"threads: expected a whole number of at least 0 \(0: all cores\), got "):
            loom.Session(threads=bad, disk_cache=False)
    for good in (0, 1, np.int64(2)):
        g = loom.Graph()
        board = g.add("Checkerboard", size=[8, 8])
        assert np.asarray(loom.Session(threads=good, disk_cache=False).run(g, board.image)).shape[:2] == (8, 8)


def test_python_node_same_in_loom_run(session, runner, tmp_path):
    # Two Python nodes and a C++ node side by side on 2 threads in `loom run`,
    # against the session's values. A linear source (HeightMap), so that the
    # float EXR files hold the values as they are.
    g = loom.Graph()
    height = g.add("HeightMap", size=[48, 40], pattern="bricks")
    outs = {"half": g.add("py.loomtest_nodes.Scale", id="half", image=height.image, factor=0.5).image,
            "double": g.add("py.loomtest_nodes.Scale", id="double", image=height.image, factor=2.0).image,
            "warp": g.add("ImageWarp", id="warp", image=height.image, method="idw", pairs=[[5, 5, 9, 7]]).image}
    for name, out in outs.items():
        g.add("SaveImage", image=out, path=f"{name}.exr", depth="float")
    g.save(tmp_path / "g.json")
    r = runner("run", tmp_path / "g.json", "--out", tmp_path / "out", "--no-cache", "--threads", "2")
    assert r.returncode == 0, r.stderr
    mine = session.run(g, list(outs.values()))
    for name, out in outs.items():
        ref = loom.Graph()
        load = ref.add("LoadImage", path=str(tmp_path / "out" / f"{name}.exr"), decode="keep")
        assert np.array_equal(np.asarray(session.run(ref, load.image)), np.asarray(mine[out])), name
    assert np.array_equal(np.asarray(mine[outs["double"]]), np.asarray(mine[outs["half"]]) * np.float32(4.0))


def test_graphs_without_python_nodes_never_load_python(runner, tmp_path):
    (tmp_path / "g.json").write_text('{"loom": 1, "nodes": {"c": {"type": "FloatConstant", "inputs": {"value": 2}}}}')
    env = dict(os.environ, LD_DEBUG="files")
    r = runner("run", tmp_path / "g.json", "--out", tmp_path, "--no-cache", "--target", "c.value", env=env)
    assert r.returncode == 0, r.stderr
    assert "libloom_util.so" in r.stderr  # the dynamic loader's trace is there
    assert "libloom_python" not in r.stderr and "libpython" not in r.stderr


def test_runner_reports_a_missing_python_module(runner, tmp_path):
    (tmp_path / "g.json").write_text('{"loom": 1, "nodes": {"x": {"type": "py.no_such_module.X"}}}')
    r = runner("run", tmp_path / "g.json", "--out", tmp_path, "--no-cache")
    assert r.returncode == 3 and "no_such_module" in r.stderr and "Python node path" in r.stderr


def test_python_and_cpp_nodes_in_parallel():
    # Eight Python chains beside eight C++ chains, on 4 threads and on 1:
    # every value is the analytic sum.
    def build():
        g = loom.Graph()
        outs = []
        for k in range(8):
            py = g.add("py.loomtest_nodes.Add", a=float(k), b=0.5)
            cpp = g.add("Math", a=py.result, b=0.25, op="add")
            py2 = g.add("py.loomtest_nodes.Add", a=cpp.result, b=1.0)
            outs.append(py2.result)
        return g, outs

    for threads in (4, 1):
        g, outs = build()
        r = loom.Session(threads=threads, disk_cache=False).run(g, outs)
        assert [r[o] for o in outs] == [k + 1.75 for k in range(8)]


def test_rerun_recomputes_only_what_changed(session):
    g, board, scale = scaled_board_graph(2.0)
    session.run(g, scale.image)
    r = session.run(g, [scale.image], set={"scale.factor": 4.0})
    assert r.nodes["board"]["status"] == "cached" and r.nodes["scale"]["status"] == "ran"
    r = session.run(g, [scale.image])
    assert r.nodes["scale"]["status"] == "cached"


def test_editing_a_python_node_invalidates_its_results(session):
    def declare(offset):
        namespace = {"loom": loom}
        exec(f"""
@loom.node(inputs={{"x": loom.In("Float", 1.0)}}, outputs={{"y": "Float"}}, name="Edited")
def edited(x):
    return x + {offset}
""", namespace)

    declare(1.0)
    g = loom.Graph()
    n = g.add("py.Edited", x=2.0)
    assert session.run(g, n.y) == 3.0
    declare(10.0)
    assert session.run(g, n.y) == 12.0  # a new source: a new hash, not the cached 3.0


def test_python_node_that_raises_names_the_node(session):
    g = loom.Graph()
    g.add("py.loomtest_nodes.Raise", id="bad", message="it went wrong")
    with pytest.raises(loom.NodeError) as e:
        session.run(g, "bad.value")
    assert e.value.node == "bad" and e.value.pointer == "/nodes/bad"
    assert "ValueError: it went wrong" in str(e.value) and "loomtest_nodes.py" in str(e.value)


@pytest.mark.parametrize("kind, message", [("string", "str"), ("nan", "NaN"), ("shape", "channels")])
def test_python_node_returning_the_wrong_type(session, kind, message):
    g = loom.Graph()
    g.add("py.loomtest_nodes.WrongOutput", id="w", kind=kind)
    with pytest.raises(loom.NodeError) as e:
        session.run(g, "w.image")
    assert e.value.node == "w" and message in str(e.value)


def interrupted_run(session, graph, target):
    """Runs `target` with Ctrl-C (interrupt_main) 0.5 s in; the seconds until
    run() raised KeyboardInterrupt."""
    threading.Timer(0.5, _thread.interrupt_main).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        session.run(graph, target)
    return time.monotonic() - start


def test_keyboard_interrupt_stops_a_body_that_never_asks_whether_it_was_cancelled():
    """Issue 37, item 13: Ctrl-C during a looping body raised nothing for 10 s."""
    g = loom.Graph()
    g.add("py.loomtest_nodes.Spin", id="spin", seconds=60.0)
    session = loom.Session(disk_cache=False)
    assert interrupted_run(session, g, "spin.spun") < 1.5
    g.add("Checkerboard", id="after", size=[8, 8])  # the session still works
    assert session.run(g, "after.image").shape == (8, 8, 3)


def test_keyboard_interrupt_cancels_a_long_node():
    g = loom.Graph()
    g.add("py.loomtest_nodes.Wait", id="wait", seconds=60.0)
    session = loom.Session(disk_cache=False)
    assert interrupted_run(session, g, "wait.waited") < 10
    g.add("Checkerboard", id="after", size=[8, 8])  # the session still works
    assert session.run(g, "after.image").shape == (8, 8, 3)


def test_keyboard_interrupt_does_not_wait_for_a_call_that_cannot_stop():
    """Ctrl-C inside a call that cannot be interrupted (a factorization; here
    a 3-s sleep in a body) reaches the caller at once; the cancelled run ends
    on its own thread and the session's next run waits for it."""
    g = loom.Graph()
    g.add("py.loomtest_nodes.Block", id="block", seconds=3.0)
    session = loom.Session(disk_cache=False)
    start = time.monotonic()
    assert interrupted_run(session, g, "block.slept") < 1.2  # the timer's 0.5 s and one 50-ms wake, not 3 s
    after = loom.Graph()
    after.add("py.loomtest_nodes.Add", id="add", a=1.0, b=2.0)
    assert session.run(after, "add.result") == 3.0
    assert time.monotonic() - start > 2.9  # the cancelled run ended before the next one


def test_a_node_is_declared_right_after_a_keyboard_interrupt():
    """Redeclaring a node after Ctrl-C (a notebook cell run again) while the
    cancelled run still ends its call that cannot stop waits for it, as the
    session's next call does, instead of being refused as "while a
    Session.run is in progress"."""
    g = loom.Graph()
    g.add("py.loomtest_nodes.Block", id="block", seconds=3.0)
    session = loom.Session(disk_cache=False)
    threading.Timer(0.5, _thread.interrupt_main).start()
    with pytest.raises(KeyboardInterrupt):
        session.run(g, "block.slept")
    namespace = {"loom": loom}
    exec("""
@loom.node(inputs={"x": loom.In("Float", 1.0)}, outputs={"y": "Float"}, name="AfterInterrupt")
def after_interrupt(x):
    return x + 1
""", namespace)
    after = loom.Graph()
    n = after.add("py.AfterInterrupt", x=2.0)
    assert session.run(after, n.y) == 3.0


def test_gil_is_released_while_the_engine_works():
    g = loom.Graph()
    board = g.add("Checkerboard", size=[2048, 2048], cells=64)
    warp = g.add("ImageWarp", image=board.image, method="rbf", pairs=[[100, 100, 200, 150], [900, 900, 800, 850]])
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    loom.Session(threads=1, disk_cache=False).run(g, warp.image)
    seconds = time.monotonic() - start
    stop.set()
    t.join()
    assert seconds > 0.05 and len(ticks) > seconds * 100  # the thread ran all along (~1000 ticks/s)


def test_progress_reaches_the_callback(session):
    g = loom.Graph()
    g.add("py.loomtest_nodes.Wait", id="wait", seconds=0.3)
    events = []
    session.run(g, "wait.waited", progress=events.append)
    kinds = [e.kind for e in events]
    assert "started" in kinds and "finished" in kinds and "progress" in kinds
    assert all(0 <= e.fraction <= 1 for e in events if e.kind == "progress")


def test_partial_images_reach_the_callback_and_the_result_is_unchanged(session):
    def graph():
        g = loom.Graph()
        box = g.add("CornellBox", id="box")
        g.add("PathTrace", id="pt", scene=box.scene, size=[32, 24], spp=16)
        return g
    events = []
    watched = session.run(graph(), "pt.image", progress=events.append)
    partials = [e for e in events if e.kind == "partial"]
    assert partials and all(e.node == "pt" and e.text == "image" for e in partials)
    assert all(e.value.shape == (24, 32, 3) for e in partials)
    assert partials[-1].fraction == 1  # the last pass is the result
    unwatched = loom.Session(disk_cache=False).run(graph(), "pt.image")
    assert np.array_equal(watched, unwatched)  # watching changed no bit


def test_help_and_completion_come_from_declarations():
    assert "ImageWarp" in dir(loom.nodes)
    doc = loom.nodes.Checkerboard.__doc__
    assert "cells: Int = 8" in doc and "image: Image" in doc
    g = loom.Graph()
    n = g.add("py.loomtest_nodes.Scale")
    assert "image" in dir(n)
    assert "the scale" in loom.nodes["py.loomtest_nodes.Scale"].__doc__


def test_image_repr_png_is_tone_mapped():
    import zlib
    lin = loom.Image(np.full((2, 3, 3), 0.5, dtype=np.float32), "linear")
    png = lin._repr_png_()
    assert png.startswith(b"\x89PNG")
    idat = png[png.index(b"IDAT") + 4:]
    raw = zlib.decompressobj().decompress(idat)
    # sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 188
    assert raw[1:4] == bytes([188, 188, 188])


def png_pixels(png):
    """The first row's first pixel of one of _display.png_bytes's PNGs (RGB, filter 0)."""
    import zlib
    raw = zlib.decompressobj().decompress(png[png.index(b"IDAT") + 4:])
    return list(raw[1:4])


def test_jupyter_shows_linear_images_through_a_view_when_asked():
    """Issue 40: loom.set_view(VIEW) shows linear images through the config's
    view, as the DisplayView node gives it; None is the default tone map."""
    try:
        views = next(i["choices"] for i in loom.nodes["DisplayView"].declaration["inputs"] if i["name"] == "view")
    except (loom.Error, KeyError, AttributeError):
        pytest.skip("plugin color (OpenColorIO) not built")
    assert "ACES 1.0 - SDR Video" in views
    grey = loom.Image(np.full((1, 2, 3), [0.18, 0.18, 0.18], dtype=np.float32), "linear")
    bright = loom.Image(np.full((1, 2, 3), [4.0, 4.0, 4.0], dtype=np.float32), "linear")
    g = loom.Graph()
    node = g.add("DisplayView", image=grey, view="ACES 1.0 - SDR Video")
    by_node = np.asarray(loom.Session(disk_cache=False).run(g, node.image))[0, 0]
    try:
        loom.set_view("ACES 1.0 - SDR Video")
        aces = png_pixels(grey._repr_png_())
        assert aces == [int(np.clip(v, 0, 1) * 255 + 0.5) for v in by_node]
        assert aces != [118, 118, 118]  # the sRGB curve's 0.18, which the filmic curve darkens
        assert png_pixels(bright._repr_png_())[0] < 255  # tone-mapped, not clipped
        with pytest.raises(loom.Error, match="did you mean"):
            loom.set_view("Standrad")
    finally:
        loom.set_view(None)
    assert png_pixels(grey._repr_png_()) == [118, 118, 118]  # sRGB(0.18) = 0.4614 -> 118


def test_an_image_names_its_colour_space_both_ways():
    """Issue 40: an image in ACEScg says so in Python (.space), a named image
    given to an input is converted from its space, and Jupyter shows it
    through the display's default view, not the sRGB curve on AP1 values.
    Reference: the published Rec.709-to-AP1 matrix (ACES TB-2014-004)."""
    try:
        loom.nodes["ColorConvert"].declaration
    except (loom.Error, KeyError, AttributeError):
        pytest.skip("plugin color (OpenColorIO) not built")
    rec709_to_ap1 = np.array([[0.6130974, 0.3395231, 0.0473795],
                              [0.0701937, 0.9163539, 0.0134524],
                              [0.0206156, 0.1095698, 0.8698146]])
    ap1 = np.array([0.5, 0.1, 0.1])
    rec709 = np.linalg.solve(rec709_to_ap1, ap1)
    session = loom.Session(disk_cache=False)
    g = loom.Graph()
    given = loom.Image(np.full((1, 2, 3), ap1, dtype=np.float32), "linear", "ACEScg")
    back = g.add("ColorConvert", image=given, to="lin_rec709")
    out = session.run(g, back.image)
    assert out.space == ""
    assert np.allclose(np.asarray(out)[0, 0], rec709, atol=1e-5)
    g = loom.Graph()
    cg = g.add("ColorConvert", image=loom.Image(np.full((1, 2, 3), rec709, dtype=np.float32)), to="ACEScg")
    named = session.run(g, cg.image)
    assert named.space == "ACEScg" and named.encoding == "linear"
    assert np.allclose(np.asarray(named)[0, 0], ap1, atol=1e-5)
    x = np.clip(rec709, 0, 1)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)  # IEC 61966-2-1
    shown = png_pixels(named._repr_png_())
    assert all(abs(s - int(v * 255 + 0.5)) <= 1 for s, v in zip(shown, srgb)), (shown, srgb)


def test_mesh_preview_is_rendered():
    try:
        loom.nodes.Render
    except loom.Error:
        pytest.skip("plugin shading not built")
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    png = loom.Mesh(v, f)._repr_png_()
    assert png.startswith(b"\x89PNG") and len(png) > 1000


def test_ctrl_c_in_loom_run_cancels_a_python_node(tmp_path):
    runner = os.environ.get("LOOM_RUNNER")
    if not runner or not os.path.exists(runner):
        pytest.skip("LOOM_RUNNER is not set to the built loom runner")
    import signal
    import subprocess
    (tmp_path / "g.json").write_text('{"loom": 1, "nodes": {"w": {"type": "py.loomtest_nodes.Wait", '
                                     '"inputs": {"seconds": 40}}}}')
    p = subprocess.Popen([runner, "run", str(tmp_path / "g.json"), "--target", "w.waited", "--no-cache"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    p.stderr.readline()  # the first progress line: the node is running
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130 and "cancelled" in err
    assert time.monotonic() - start < 10


def test_no_declarations_during_a_run(session):
    g = loom.Graph()
    g.add("py.loomtest_nodes.DeclareInside", id="d")
    with pytest.raises(loom.NodeError, match="while a Session.run is in progress"):
        session.run(g, "d.value")
