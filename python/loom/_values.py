"""Python forms of the engine's value types."""

import numpy as np

from . import _display


class Image(np.ndarray):
    """Pixels as an H×W×C float32 NumPy array (C = 1-4: gray, gray+alpha, RGB,
    RGBA; origin top-left) with its colour ``encoding``: "linear" or "srgb",
    and ``space``: the OpenColorIO colour space's name when it is not the
    encoding's own ("ACEScg" after a ColorConvert), else "".

    Images a run returns are read-only views of the engine's pixels (no copy),
    kept alive by the array. Any float32 array may be given to an Image
    input; wrap it as ``loom.Image(array, "srgb")`` to say it is encoded, or
    ``loom.Image(array, "linear", "ACEScg")`` to name its space."""

    def __new__(cls, array, encoding="linear", space=""):
        if encoding not in ("linear", "srgb"):
            raise ValueError(f'encoding must be "linear" or "srgb", got {encoding!r}')
        obj = np.asarray(array).view(cls)
        obj.encoding = encoding
        obj.space = str(space)
        return obj

    def __array_finalize__(self, obj):
        self.encoding = getattr(obj, "encoding", "linear")
        self.space = getattr(obj, "space", "")

    def _repr_png_(self):
        if self.ndim not in (2, 3) or self.size == 0:
            return None
        return _display.png_bytes(_display.image_display(np.asarray(self), self.encoding, self.space))


class Mesh:
    """A triangle mesh: ``vertices`` #V×3 float64, ``faces`` #F×3 int32
    (counter-clockwise seen from outside), optional per-vertex ``uv`` #V×2,
    ``normals`` #V×3 and linear RGB ``colors`` #V×3 (None when absent)."""

    def __init__(self, vertices, faces, uv=None, normals=None, colors=None):
        self.vertices = np.asarray(vertices)
        self.faces = np.asarray(faces)
        self.uv = None if uv is None else np.asarray(uv)
        self.normals = None if normals is None else np.asarray(normals)
        self.colors = None if colors is None else np.asarray(colors)

    def __repr__(self):
        extras = [n for n in ("uv", "normals", "colors") if getattr(self, n) is not None]
        return (f"<loom.Mesh {len(self.vertices)} vertices, {len(self.faces)} faces"
                + (", " + ", ".join(extras) if extras else "") + ">")

    def _repr_png_(self):
        from ._errors import Error
        try:
            return _display.mesh_preview(self)._repr_png_()
        except Error:  # no shading plugin, or nothing to draw: Jupyter shows the text form
            return None


class PointSet:
    """Points: ``points`` #P×3, optional ``radius`` #P and linear RGB ``colors`` #P×3."""

    def __init__(self, points, radius=None, colors=None):
        self.points = np.asarray(points)
        self.radius = None if radius is None else np.asarray(radius)
        self.colors = None if colors is None else np.asarray(colors)

    def __repr__(self):
        return f"<loom.PointSet {len(self.points)} points>"


class Polylines:
    """Line segments: ``points`` #P×3, ``edges`` #E×2 index pairs, optional ``colors`` #P×3."""

    def __init__(self, points, edges, colors=None):
        self.points = np.asarray(points)
        self.edges = np.asarray(edges)
        self.colors = None if colors is None else np.asarray(colors)

    def __repr__(self):
        return f"<loom.Polylines {len(self.points)} points, {len(self.edges)} segments>"
