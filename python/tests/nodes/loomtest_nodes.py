"""Python nodes for the tests (type "py.loomtest_nodes.NAME")."""

import time

import numpy as np

import loom


@loom.node(inputs={"image": "Image", "factor": loom.In("Float", 2.0, "the scale", range=(-100, 100))},
           outputs={"image": loom.Out("Image", "image * factor")})
def Scale(image, factor):
    """Multiplies every channel by factor."""
    return loom.Image(np.asarray(image) * np.float32(factor), image.encoding)


@loom.node(inputs={"a": loom.In("Float", 0.0), "b": loom.In("Float", 0.0)}, outputs={"result": "Float"})
def Add(a, b):
    """a + b, like Math with op add."""
    return a + b


@loom.node(inputs={"seconds": loom.In("Float", 30.0, "how long to spin at most")}, outputs={"spun": "Float"})
def Spin(seconds):
    """Loops until `seconds` pass, never asking whether the run was cancelled."""
    start = time.monotonic()
    while time.monotonic() - start < seconds:
        pass
    return time.monotonic() - start


@loom.node(inputs={"seconds": loom.In("Float", 30.0, "how long to wait at most")}, outputs={"waited": "Float"})
def Wait(seconds, ctx):
    """Waits until cancelled or `seconds` pass; returns the time waited."""
    start = time.monotonic()
    while time.monotonic() - start < seconds:
        if ctx.cancelled():
            raise loom.Error("cancelled")
        time.sleep(0.01)
        ctx.progress(time.monotonic() - start, seconds, "waiting")
    return time.monotonic() - start


@loom.node(inputs={"seconds": loom.In("Float", 3.0, "how long the call lasts")}, outputs={"slept": "Float"})
def Block(seconds):
    """One long call that nothing can interrupt (as a sparse factorization):
    a KeyboardInterrupt raised in this thread waits for it to return."""
    start = time.monotonic()
    time.sleep(seconds)
    return time.monotonic() - start


@loom.node(inputs={"message": loom.In("String", "boom")}, outputs={"value": "Float"})
def Raise(message):
    """Raises ValueError(message)."""
    raise ValueError(message)


@loom.node(inputs={"kind": loom.In("Enum", "string", choices=["string", "nan", "shape"])},
           outputs={"image": "Image"})
def WrongOutput(kind):
    """Returns what an Image output cannot take."""
    if kind == "string":
        return "not an image"
    if kind == "nan":
        return np.full((4, 4, 3), np.nan, dtype=np.float32)
    return np.zeros((4, 4, 7), dtype=np.float32)


@loom.node(inputs={"image": "Image"},
           outputs={"mean": loom.Out("FloatList", "per channel"), "size": loom.Out("Vec2i", "width, height")})
def Stats(image):
    """Mean of each channel, and the size."""
    a = np.asarray(image)
    return {"mean": a.reshape(-1, a.shape[2]).mean(axis=0).tolist(), "size": [a.shape[1], a.shape[0]]}


@loom.node(outputs={"value": "Float"})
def DeclareInside():
    """Declares a node type while it runs (refused: a run reads the registry)."""
    @loom.node(outputs={"v": "Float"}, name="Inner")
    def inner():
        return 1.0

    return 0.0
