"""Loom from Python: build graphs in code, run them in a Session and get NumPy
arrays back, show images and meshes in Jupyter, write nodes in Python.

    import loom
    g = loom.Graph()
    board = g.add("Checkerboard", size=[256, 256], cells=8)
    warp = g.add("ImageWarp", image=board.image, method="rbf", pairs=[[[0, 0], [10, 5]]])
    image = loom.Session().run(g, warp.image)     # an H×W×C float32 array

``loom.nodes`` lists every node type (help(loom.nodes.ImageWarp)). See
docs/python.md."""

from ._errors import Error, GraphError, InputError, NodeError
from ._loom import Context, Value
from ._values import Image, Mesh, PointSet, Polylines
from ._graph import Graph, Node, Output, load
from ._session import Event, Result, Session
from ._python_nodes import In, Out, node, node_path
from ._docs import nodes
from ._display import set_view

__all__ = ["Error", "GraphError", "InputError", "NodeError", "Context", "Value", "Image", "Mesh", "PointSet",
           "Polylines", "Graph", "Node", "Output", "load", "Event", "Result", "Session", "In", "Out", "node",
           "node_path", "nodes", "set_view"]
