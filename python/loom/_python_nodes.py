"""Nodes written in Python: @loom.node declares a node type with the same
declaration language as a C++ node (types, defaults, ranges, choices, docs).
Its body receives and returns the values Session.run returns (NumPy arrays,
loom.Mesh, numbers, dicts). It is hashed by its source, so editing the
function invalidates its cached results, and runs on the engine's threads
beside C++ nodes (only Python bodies share the GIL).

A node in a module on the Python node path, type "py.MODULE.NAME", also runs
in `loom run` and the editor (the `python` plugin imports the module). The
path: the folders of LOOM_PYTHON_PATH (separated by ':'), then
$XDG_DATA_HOME/loom/python (~/.local/share/loom/python), then Loom's own
share/loom/python; then Python's sys.path."""

import hashlib
import importlib
import inspect
import os
import sys

from . import _docs, _loom
from ._errors import Error


class In:
    """An input: its type ("Float", "Image", "Enum", ...), default (None:
    required unless optional), doc, range (min, max) for numbers, choices for
    an Enum."""

    def __init__(self, type, default=None, doc="", range=None, choices=None, optional=False):
        self.type, self.default, self.doc = type, default, doc
        self.range, self.choices, self.optional = range, choices, optional

    def declaration(self, name):
        """The declaration in the engine's vocabulary (as group interfaces
        and `loom nodes --json` write it), unset keys left out."""
        low, high = (None, None) if self.range is None else tuple(self.range)
        keys = {"type": self.type, "default": self.default, "description": self.doc or None,
                "min": low, "max": high, "choices": None if self.choices is None else list(self.choices),
                "optional": self.optional or None}
        return {"name": name, **{k: v for k, v in keys.items() if v is not None}}


class Out:
    """An output: its type and doc."""

    def __init__(self, type, doc=""):
        self.type, self.doc = type, doc

    def declaration(self, name):
        return {"name": name, "type": self.type, "description": self.doc}


def _declarations(spec, cls, what):
    out = []
    for name, d in (spec or {}).items():
        if isinstance(d, str):
            d = cls(d)
        if not isinstance(d, cls):
            raise Error(f"{what} \"{name}\": expected a type name or loom.{cls.__name__}(...), got {d!r}")
        out.append(d.declaration(name))
    return out


def _source_hash(fn, declaration):
    try:
        source = inspect.getsource(fn)
    except (OSError, TypeError):  # defined where no source is kept (exec)
        source = repr(fn.__code__.co_code) + repr(fn.__code__.co_consts)
    digest = hashlib.blake2b((source + repr(declaration)).encode(), digest_size=8).digest()
    return int.from_bytes(digest, "little")


def _source_file(fn):
    """The module file defining ``fn`` (what `loom run --watch` follows), or "" (a notebook)."""
    try:
        file = inspect.getsourcefile(fn)
    except TypeError:
        return ""
    return os.path.abspath(file) if file and os.path.isfile(file) else ""


_declaration_count = 0


def declarations():
    """How many node declarations this process has seen (prepared graphs are
    checked again after a new one)."""
    return _declaration_count


def type_name(module, name):
    return "py." + ("" if module == "__main__" else module + ".") + name


def node(inputs=None, outputs=None, name=None, doc=None, sink=False, time_dependent=False,
         nondeterministic=False, version=1):
    """Declares a Python function as a node type:

        @loom.node(inputs={"image": "Image", "gamma": loom.In("Float", 2.2, "exponent", range=(0.1, 10))},
                   outputs={"image": loom.Out("Image", "the corrected image")})
        def Gamma(image, gamma):
            return image ** (1 / gamma)

    The type is "py.MODULE.NAME" (NAME: ``name`` or the function's; "py.NAME"
    for a notebook or script). Inputs arrive as keyword arguments (None for an
    optional input left unset); a parameter named ``ctx`` receives the node's
    context (progress, cancelled(), seed, frame, warn). Return the value of a
    single output, or a tuple or dict for several. ``version`` is part of the
    hash: bump it when a helper the function calls changes."""

    def declare(fn):
        node_name = name or fn.__name__
        module = fn.__module__ or "__main__"
        full = type_name(module, node_name)
        ins = _declarations(inputs, In, "input")
        outs = _declarations(outputs, Out, "output")
        params = inspect.signature(fn).parameters
        takes_all = any(p.kind == p.VAR_KEYWORD for p in params.values())
        for i in ins:
            if i["name"] not in params and not takes_all:
                raise Error(f"{full}: input \"{i['name']}\" is not a parameter of {fn.__name__}")
        flags = {"sink": sink, "time_dependent": time_dependent, "nondeterministic": nondeterministic,
                 "source_file": _source_file(fn)}
        description = doc or inspect.getdoc(fn) or ""
        declaration = (ins, outs, flags, description, version)
        # A run Ctrl-C interrupted may still be ending its cancelled work (it
        # counts as running, and reads the node types): wait for it, as a
        # session's next call does, so that redeclaring a node right after
        # Ctrl-C (a notebook cell run again) is not refused.
        from . import _session
        _session._settle_sessions()
        _loom.declare_node(full, module, fn, description, ins, outs, flags, _source_hash(fn, declaration),
                           "ctx" in params)
        _docs.forget()
        global _declaration_count
        _declaration_count += 1
        fn.loom_type = full
        return fn

    return declare


def node_path():
    """The folders Python node modules are imported from, in order."""
    path = [p for p in os.environ.get("LOOM_PYTHON_PATH", "").split(":") if p]
    data = os.environ.get("XDG_DATA_HOME") or os.path.join(os.path.expanduser("~"), ".local", "share")
    path.append(os.path.join(data, "loom", "python"))
    here = os.path.dirname(os.path.abspath(__file__))
    for share in (os.path.join(here, "..", "..", "share", "loom", "python"),
                  os.path.join(here, "..", "..", "..", "..", "share", "loom", "python")):
        if os.path.isdir(share):
            path.append(os.path.normpath(share))
            break
    return path


_imported = {}  # module name -> (file, its modification stamp) when the provider imported it


def _stamp(file):
    try:
        st = os.stat(file)
        return (st.st_mtime_ns, st.st_size)
    except (OSError, TypeError):
        return None


def _import_current(module):
    """Imports ``module``, or reloads it when its file changed since (a `loom run
    --watch` rerun after an edit must run the new definitions, not the old)."""
    loaded = sys.modules.get(module)
    if loaded is not None and module in _imported and _stamp(_imported[module][0]) != _imported[module][1]:
        loaded = importlib.reload(loaded)
    elif loaded is None:
        loaded = importlib.import_module(module)
    file = getattr(loaded, "__file__", None)
    _imported[module] = (file, _stamp(file))


def import_node_module(type):
    """Imports the module a "py.MODULE.NAME" type names (the `python` plugin's provider)."""
    module, _, _ = type[len("py."):].rpartition(".")
    if not module:
        raise ImportError(f"\"{type}\" names no module: Python node types in graph files are py.MODULE.NAME; "
                          "a node declared in a notebook or script exists only in that process")
    for folder in reversed(node_path()):
        if folder not in sys.path:
            sys.path.insert(0, folder)
    try:
        _import_current(module)
    except ModuleNotFoundError as e:
        if e.name != module:
            raise
        raise ImportError(f"no module \"{module}\" on the Python node path ({':'.join(node_path())}) "
                          "or sys.path") from None
