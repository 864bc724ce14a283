"""The Python twin of Math(op=add), for bench_python (type "py.bench_nodes.Add")."""

import loom


@loom.node(inputs={"a": loom.In("Float", 0.0), "b": loom.In("Float", 0.0)}, outputs={"result": "Float"})
def Add(a, b):
    """a + b."""
    return a + b
