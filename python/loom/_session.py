"""Running graphs: a Session is one `loom run` process kept alive (threads,
memory cache, disk cache); run() returns Python values."""

import atexit
import collections
import collections.abc
import json
import numbers
import os
import sys
import weakref

from . import _loom
from ._errors import Error, NodeError
from ._graph import Graph, Node, Output

Event = collections.namedtuple("Event", "kind node fraction text value", defaults=(None,))
Event.__doc__ = """What a run reports: kind is "started", "progress" (fraction in [0, 1],
text the label), "message", "warning", "finished" (fraction: seconds, text: the
status), "frame" (node: the frame number) or "partial" (a value so far of output
text, e.g. PathTrace's image after a pass, in value; fraction: how far; only shown,
never the result)."""


def _target_text(t):
    if isinstance(t, (Output, Node)):
        return str(t) if isinstance(t, Output) else t.id
    if isinstance(t, str):
        return t
    raise TypeError(f"a target is an output (node.image), a node or \"ID.OUTPUT\", got {type(t).__name__}")


def _frames(frames):
    if frames is None:
        return None
    if isinstance(frames, int):
        return (frames, frames)
    if isinstance(frames, range):
        if frames.step != 1 or len(frames) == 0:
            raise ValueError("frames: a range of step 1 with at least one frame")
        return (frames.start, frames.stop - 1)
    first, last = frames
    return (int(first), int(last))


class _Bar:
    """A tqdm bar over the nodes of a run when tqdm is installed, else nothing."""

    def __init__(self, total):
        try:
            from tqdm.auto import tqdm
            self.bar = tqdm(total=total, unit="node", leave=False)
        except ImportError:
            self.bar = None

    def __call__(self, e):
        if self.bar is None:
            return
        if e.kind == "finished":
            self.bar.update(1)
        elif e.kind in ("started", "progress"):
            self.bar.set_postfix_str(f"{e.node} {e.fraction * 100:.0f}% {e.text}".strip())

    def close(self):
        if self.bar is not None:
            self.bar.close()


class Result(collections.abc.Mapping):
    """The outputs of a run by target ("ID.OUTPUT", or an Output), the
    ``nodes`` reports (status, seconds, runs, cache hits, error), and
    ``seconds``. An output kept at several frames is the list of its values,
    one per frame."""

    def __init__(self, graph, raw):
        self._graph = graph
        self.nodes = raw["nodes"]
        self.seconds = raw["seconds"]
        self.frames = raw["frames"]
        self.cancelled = raw["cancelled"]
        self._values = dict(raw["outputs"])  # by "ID.OUTPUT", named by the engine

    def __getitem__(self, key):
        key = _target_text(key)
        if key in self._values:
            return self._values[key]
        if "." not in key:  # a node: its one output
            mine = [k for k in self._values if k.startswith(key + ".")]
            if len(mine) == 1:
                return self._values[mine[0]]
        raise KeyError(f"{key} is not among this run's outputs ({', '.join(self._values) or 'none'})")

    def __iter__(self):
        return iter(self._values)

    def __len__(self):
        return len(self._values)

    def __repr__(self):
        return f"<loom.Result {list(self._values)} in {self.seconds:.3f} s>"


class Session:
    """Evaluates graphs like one `loom run` process kept alive: ``threads``
    (0: all cores), the memory cache (re-running after a change recomputes
    only what depends on it), the disk cache (True: the runner's folder,
    $XDG_CACHE_HOME/loom; a path; or False) and the output folder relative
    paths of Save nodes resolve against."""

    def __init__(self, threads=0, disk_cache=True, output_dir=".", allow_outside_output=False):
        # As `loom run --threads`: -1 meant all cores and 1.5 one thread, silently.
        if isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 0:
            raise ValueError(f"threads: expected a whole number of at least 0 (0: all cores), got {threads!r}")
        cache = None if disk_cache is False or disk_cache is None else ("" if disk_cache is True else os.fspath(disk_cache))
        self._core = _loom.SessionCore(int(threads), cache, os.fspath(output_dir), bool(allow_outside_output))
        _sessions.add(self)

    def run(self, graph, targets=None, frames=None, set=None, progress=None):
        """Runs ``graph`` and returns its outputs.

        targets: None (every sink), one output (``node.image``: its value is
        returned), a node, "ID.OUTPUT", or a list of these (a Result is
        returned). frames: a frame, (first, last) or a range. set: {"ID.INPUT":
        value} applied to a copy of the graph (like `loom run --set`).
        progress: a callable taking an Event, or True for a progress bar.

        Raises loom.GraphError (invalid graph), loom.NodeError (a node
        failed: its id and JSON pointer), KeyboardInterrupt (Ctrl-C cancels the
        running nodes first)."""
        if not isinstance(graph, Graph):
            raise TypeError(f"run() takes a loom.Graph, got {type(graph).__name__}")
        single = isinstance(targets, (Output, Node, str))
        target_list = [] if targets is None else [targets] if single else list(targets)
        sets = []
        if set:
            graph, sets = _with_values(graph, set)
        prepared = graph._prepare(sets)
        bar = _Bar(len(graph)) if progress is True else None
        callback = None
        if bar is not None:
            callback = lambda *a: bar(Event(*a))
        elif callable(progress):
            callback = lambda *a: progress(Event(*a))
        try:
            raw = self._core.run(prepared, [_target_text(t) for t in target_list], _frames(frames), callback)
        finally:
            if bar is not None:
                bar.close()
        result = Result(graph, raw)
        failed = [id for id, r in raw["nodes"].items() if r["status"] == "failed"]
        if failed:
            raise NodeError(failed[0], raw["nodes"][failed[0]]["error"], result)
        if single:
            return result[targets]
        return result

    @property
    def cache_entries(self):
        return self._core.cache_entries()

    def clear_cache(self):
        self._core.clear_cache()


def _with_values(graph, values):
    """The graph and the ``--set`` assignments for ``values``: a value with a
    JSON form is given as `loom run --set` gives it (the engine resolves the
    address: group interface inputs and inner paths too); an in-memory value
    (an array) is held by a copy of the graph."""
    g = Graph()
    g._doc = graph.to_json()
    g._held = {id: dict(inputs) for id, inputs in graph._held.items()}
    g.file = graph.file
    g._changed()
    sets = []
    for key, value in values.items():
        if not isinstance(key, str) or "." not in key.strip("."):
            raise Error(f"set: expected \"ID.INPUT\", got \"{key}\"")
        try:
            sets.append(f"{key}={json.dumps(value, allow_nan=False)}")
            continue
        except (TypeError, ValueError):
            pass
        node, _, input = key.rpartition(".")
        g[node][input] = value
    return g, sets


# A run Ctrl-C interrupted ends its cancelled work on its own thread while
# the KeyboardInterrupt reaches the caller; before the interpreter shuts down
# (when no thread may take the GIL any more) every such run is waited for.
_sessions = weakref.WeakSet()


@atexit.register
def _settle_sessions():
    for session in list(_sessions):
        session._core.settle()


_default = None


def default_session():
    """A session without a disk cache, for previews."""
    global _default
    if _default is None:
        _default = Session(disk_cache=False)
    return _default
