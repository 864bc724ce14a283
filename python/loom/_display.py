"""Pictures for Jupyter: PNG bytes of an image (tone-mapped when linear, or
through an OpenColorIO view: set_view) and a small rendered preview of a mesh
(through the engine's own Render node)."""

import struct
import zlib

import numpy as np


_view = None  # how linear images are shown: None (Reinhard, then sRGB), or a DisplayView view


def set_view(view):
    """How Jupyter shows linear images. None (the default): values above 1
    tone-mapped by Reinhard, x / (1 + x), then the sRGB curve. A view name:
    the OpenColorIO view the DisplayView node applies ("Standard", "ACES 1.0 -
    SDR Video", "Raw" in Loom's config; $OCIO's views when set), run by the
    engine, as a graph would. Raises loom.Error for a view the config does
    not have (the colour plugin is needed, with OpenColorIO)."""
    global _view
    if view is not None:
        from ._docs import describe, did_you_mean
        from ._errors import Error
        try:
            choices = next(i["choices"] for i in describe("DisplayView")["inputs"] if i["name"] == "view")
        except Error as e:
            raise Error(f"set_view: the DisplayView node is not available ({e})") from None
        if view not in choices:
            raise Error(f"set_view: no view {view!r}; the display's views are {', '.join(choices)}"
                        + did_you_mean(view, choices))
    _view = view


def image_display(pixels, encoding, space=""):
    """8-bit pixels of an image as Jupyter shows it: a linear RGB(A) image
    through the view set by set_view(), or, when it names its colour space
    (ACEScg), through that view or the display's default one (Reinhard and
    the sRGB curve would read its values as Rec.709's); else to_display()."""
    a = np.asarray(pixels, dtype=np.float32)
    viewable = encoding == "linear" and a.ndim == 3 and a.shape[2] in (3, 4)
    if not viewable or (_view is None and not space):
        return to_display(a, encoding)
    from ._graph import Graph
    from ._session import default_session
    from ._values import Image
    g = Graph()
    inputs = {"image": Image(a, "linear", space)}
    if _view is not None:
        inputs["view"] = _view
    view = g.add("DisplayView", **inputs)
    return to_display(np.asarray(default_session().run(g, view.image)), "srgb")


def srgb_encode(linear):
    """IEC 61966-2-1: the sRGB transfer function, per value."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def to_display(pixels, encoding):
    """8-bit pixels: linear values are tone-mapped (Reinhard, x / (1 + x), only
    when the image holds values above 1) and sRGB-encoded; encoded values are
    clipped. Alpha is kept as is."""
    a = np.asarray(pixels, dtype=np.float32)
    if a.ndim == 2:
        a = a[:, :, None]
    color = a[:, :, : 3 if a.shape[2] >= 3 else 1]
    if encoding == "linear":
        if color.size and float(color.max()) > 1.0:
            color = color / (1.0 + color)
        color = srgb_encode(color)
    out = color
    if a.shape[2] in (2, 4):
        out = np.concatenate([color, a[:, :, -1:]], axis=2)
    return (np.clip(out, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def png_bytes(rgb8):
    """A PNG file of an H×W×C uint8 array (C 1-4), written with zlib."""
    h, w, c = rgb8.shape
    color_type = {1: 0, 2: 4, 3: 2, 4: 6}[c]
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def mesh_preview(mesh, width=320, height=240):
    """The mesh drawn by Render (plugin shading), lit from the camera's side,
    with a camera framing it."""
    from ._graph import Graph
    from ._session import default_session
    g = Graph()
    obj = g.add("Object", mesh=mesh)
    light = g.add("Light", kind="directional", direction=[-0.4, -0.6, -1.0], intensity=3.0)
    scene = g.add("MergeScenes", a=obj.scene, b=light.scene)
    render = g.add("Render", scene=scene.scene, width=width, height=height, shadows="off", extra_images=False)
    return default_session().run(g, render.image)
