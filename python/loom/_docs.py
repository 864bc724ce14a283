"""Node types as Python sees them: their declarations, formatted like
`loom nodes TYPE`, for help(), tab completion and "did you mean"."""

import json

from . import _loom

_cache = {}


def forget():
    """Called when a Python node is (re)declared."""
    _cache.clear()


def describe(type):
    """The declaration of a node type (what `loom nodes TYPE --json` prints)."""
    if type not in _cache:
        d = _loom.describe_node_type(type)
        d["name"] = type
        d["input_names"] = [i["name"] for i in d["inputs"]]
        _cache[type] = d
    return _cache[type]


def did_you_mean(name, candidates):
    near = _loom.near_names(name, list(candidates))
    return "; did you mean " + " or ".join(f'"{n}"' for n in near) + "?" if near else ""


def _value(v):
    return json.dumps(v, separators=(",", ":"))


def reference(type):
    """The reference text of a node type."""
    d = describe(type)
    lines = [f"{type}  (plugin {d['plugin']}, version {d['version']})", "", d["description"], ""]
    if d["flags"]:
        lines += ["Flags: " + ", ".join(d["flags"]), ""]
    lines.append("Inputs (node[\"NAME\"] = value, or g.add(..., NAME=value)):")
    for i in d["inputs"]:
        default = "required" if i["required"] else ("optional" if i["default"] is None else "= " + _value(i["default"]))
        extra = ""
        if "min" in i or "max" in i:
            extra += f", range [{i.get('min', '-inf')}, {i.get('max', 'inf')}]"
        if "choices" in i:
            extra += ", one of " + " ".join(i["choices"])
        lines.append(f"    {i['name']}: {i['type']} {default}{extra}\n        {i['description']}")
    lines.append("Outputs (node.NAME):")
    for o in d["outputs"]:
        lines.append(f"    {o['name']}: {o['type']}\n        {o['description']}")
    return "\n".join(lines)


class _NodeTypes:
    """Every node type, by name: ``help(loom.nodes.ImageWarp)`` shows its
    inputs and outputs; ``dir(loom.nodes)`` lists them."""

    def __dir__(self):
        return sorted(_loom.describe_node_types())

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        text = reference(name)
        # A class, so that help() shows the reference as its documentation.
        return type(name, (NodeType,), {"__doc__": text, "name": name, "declaration": describe(name)})

    def __getitem__(self, name):
        return self.__getattr__(name)

    def __repr__(self):
        return f"<loom.nodes: {len(self.__dir__())} node types>"


class NodeType:
    """A node type (see loom.nodes)."""


nodes = _NodeTypes()
