"""Graphs from code: the same JSON document a graph file holds (what the
editor edits), built with add() and attribute links."""

import copy
import os
import re

from . import _loom
from ._errors import Error, InputError
from . import _docs, _python_nodes


class Output:
    """One output of a node: give it to another node's input to link them."""

    def __init__(self, node, name):
        self.node = node
        self.name = name

    def __str__(self):
        return f"{self.node.id}.{self.name}"

    def __repr__(self):
        return f"<loom.Output {self}>"


class Node:
    """A node of a graph. ``node.OUTPUT`` is an output (for links and run
    targets); ``node["INPUT"]`` reads or sets an input; ``node.set(**inputs)``
    sets several."""

    def __init__(self, graph, id):
        object.__setattr__(self, "_graph", graph)
        object.__setattr__(self, "id", id)

    @property
    def type(self):
        return self._graph._doc["nodes"][self.id]["type"]

    @property
    def outputs(self):
        return [o["name"] for o in _docs.describe(self.type)["outputs"]]

    @property
    def inputs(self):
        return [i["name"] for i in _docs.describe(self.type)["inputs"]]

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        outputs = self.outputs
        if name in outputs:
            return Output(self, name)
        hint = _docs.did_you_mean(name, outputs)
        extra = f' ("{name}" is an input: node["{name}"])' if name in self.inputs else ""
        raise AttributeError(f"{self.type} node \"{self.id}\" has no output \"{name}\"{hint}{extra}")

    def __setattr__(self, name, value):
        raise AttributeError(f'set inputs with node["{name}"] = value or node.set({name}=...)')

    def __dir__(self):
        return sorted(set(self.outputs) | {"id", "type", "inputs", "outputs", "set"})

    def __getitem__(self, input):
        return self._graph._get_input(self.id, input)

    def __setitem__(self, input, value):
        self._graph._set_input(self.id, input, value)

    def set(self, **inputs):
        for name, value in inputs.items():
            self._graph._set_input(self.id, name, value)
        return self

    @property
    def __doc__(self):
        return _docs.reference(self.type)

    def __repr__(self):
        return f"<loom.Node {self.id}: {self.type}>"


def _auto_id(type, taken):
    base = re.sub(r"[^0-9A-Za-z_]", "_", type.split(".")[-1]).lower() or "node"
    id, k = base, 2
    while id in taken:
        id, k = f"{base}_{k}", k + 1
    return id


class Graph:
    """A graph of nodes. ``g.add(TYPE, **inputs)`` adds one; ``g["id"]`` is a
    node; ``g.save(path)`` writes a graph file like the editor's; run it with a
    loom.Session."""

    def __init__(self, seed=0, time=None):
        self._doc = {"loom": 1, "seed": seed, "nodes": {}}
        if time is not None:
            start, end, fps = time
            self._doc["time"] = {"start": start, "end": end, "fps": fps}
        self._held = {}
        self.file = ""
        self._changed()

    def _changed(self):
        self._prepared = None  # validated for the engine on the next run

    def _prepare(self, sets=()):
        """The graph checked and ready for Session.run, with ``sets`` applied
        (``ID.INPUT=JSON``, as `loom run --set`), kept until it changes (or a
        Python node is declared again)."""
        key = (_python_nodes.declarations(), tuple(sets))
        if self._prepared is None or self._prepared[0] != key:
            self._prepared = (key, _loom.prepare(self._doc, self.file, self._held, list(sets)))
        return self._prepared[1]

    # --- nodes -----------------------------------------------------------
    def add(self, type, id=None, **inputs):
        """Adds a node of ``type`` (a name `loom.nodes` lists) with these
        inputs: values, NumPy arrays and meshes, or other nodes' outputs."""
        type = getattr(type, "loom_type", type)  # a function declared with @loom.node
        _docs.describe(type)  # unknown type: "did you mean"
        if id is None:
            id = _auto_id(type, self._doc["nodes"])
        elif id in self._doc["nodes"]:
            raise Error(f"/nodes/{id}: a node with this id exists already")
        elif not re.fullmatch(r"[A-Za-z0-9_\-]+", id):
            raise Error(f"/nodes/{id}: node ids are letters, digits, '_' and '-'")
        self._doc["nodes"][id] = {"type": type, "inputs": {}}
        self._changed()
        try:
            for name, value in inputs.items():
                self._set_input(id, name, value)
        except Exception:
            del self._doc["nodes"][id]
            self._held.pop(id, None)
            raise
        return Node(self, id)

    def __getitem__(self, id):
        if id not in self._doc["nodes"]:
            raise KeyError(f"no node \"{id}\"{_docs.did_you_mean(id, list(self._doc['nodes']))}")
        return Node(self, id)

    def __contains__(self, id):
        return id in self._doc["nodes"]

    def __iter__(self):
        return iter(list(self._doc["nodes"]))

    def __len__(self):
        return len(self._doc["nodes"])

    def remove(self, id):
        self[id]
        del self._doc["nodes"][id]
        self._held.pop(id, None)
        self._changed()

    @property
    def seed(self):
        return self._doc.get("seed", 0)

    @seed.setter
    def seed(self, value):
        self._doc["seed"] = int(value)
        self._changed()

    # --- inputs ----------------------------------------------------------
    def _get_input(self, id, input):
        if input in self._held.get(id, {}):
            return self._held[id][input].value
        value = self._doc["nodes"][id].get("inputs", {}).get(input)
        if isinstance(value, dict) and set(value) == {"from"}:
            node, _, output = value["from"].partition(".")
            return Output(Node(self, node), output)
        if value is None and input not in _docs.describe(self[id].type)["input_names"]:
            raise KeyError(f"{self[id].type} has no input \"{input}\""
                           f"{_docs.did_you_mean(input, _docs.describe(self[id].type)['input_names'])}")
        return copy.deepcopy(value)

    def _set_input(self, id, input, value):
        node = self._doc["nodes"][id]
        self._changed()
        try:
            if isinstance(value, Node):
                outs = value.outputs
                if len(outs) != 1:
                    raise Error(f"node \"{value.id}\" has {len(outs)} outputs: name one ({', '.join(outs)})")
                value = Output(value, outs[0])
            if isinstance(value, Output):
                if value.node._graph is not self:
                    raise Error(f"{value} belongs to another graph")
                _loom.check_link(value.node.type, value.name, node["type"], input)
                node.setdefault("inputs", {})[input] = {"from": str(value)}
                self._held.get(id, {}).pop(input, None)
                return
            kind, payload = _loom.check_input(node["type"], input, value)
        except Error as e:
            raise InputError(id, input, str(e)) from None
        if kind == "held":
            self._held.setdefault(id, {})[input] = payload
            node.get("inputs", {}).pop(input, None)
        else:
            node.setdefault("inputs", {})[input] = payload
            self._held.get(id, {}).pop(input, None)

    # --- files -----------------------------------------------------------
    def to_json(self):
        """The graph file's JSON document (a copy)."""
        return copy.deepcopy(self._doc)

    def save(self, path):
        """Writes the graph file as the editor does (written, then renamed)."""
        for id, inputs in self._held.items():
            for input in inputs:
                raise Error(f"/nodes/{id}/inputs/{input}: holds an in-memory value, which a graph file "
                            "cannot: save it (SaveImage, SaveMesh) and load it with a node instead")
        for where, type in _node_types(self._doc):
            if type.startswith("py.") and "." not in type[len("py."):]:
                raise Error(f"{where}/type: \"{type}\" is defined in this notebook or script (__main__), which "
                            "no other process can import: `loom run` and the editor could not load the saved "
                            "graph. Move the function into a module on the Python node path "
                            f"({os.pathsep.join(_python_nodes.node_path())}) and use \"py.MODULE."
                            f"{type[len('py.'):]}\"")
        _loom.save_graph(self._doc, os.fspath(path))
        self.file = os.path.abspath(path)

    def __repr__(self):
        return f"<loom.Graph {len(self)} nodes{' from ' + self.file if self.file else ''}>"


def _node_types(doc):
    """(JSON pointer, type) of every node of a graph document, its inline groups' included."""
    for id, node in doc.get("nodes", {}).items():
        if isinstance(node, dict) and isinstance(node.get("type"), str):
            yield f"/nodes/{id}", node["type"]
    for name, group in doc.get("groups", {}).items():
        for id, node in (group.get("nodes", {}) if isinstance(group, dict) else {}).items():
            if isinstance(node, dict) and isinstance(node.get("type"), str):
                yield f"/groups/{name}/nodes/{id}", node["type"]


def load(path):
    """Reads a graph file (errors name the file and the JSON pointer)."""
    doc, file = _loom.load_graph(os.fspath(path))
    g = Graph()
    g._doc = doc
    g.file = file
    g._changed()
    return g
