"""The engine's errors as Python exceptions."""


class Error(Exception):
    """An engine error: a message a user can act on."""


class GraphError(Error):
    """An invalid graph. ``issues`` lists (JSON pointer, message); ``pointer``
    and ``node`` name the first."""

    def __init__(self, message, file="", issues=()):
        super().__init__(message)
        self.file = file
        self.issues = list(issues)
        self.pointer = self.issues[0][0] if self.issues else ""
        parts = self.pointer.split("/")
        self.node = parts[2] if len(parts) > 2 and parts[1] == "nodes" else None


class NodeError(Error):
    """A node failed while running: ``node`` is its id, ``pointer`` its JSON
    pointer in the graph (/nodes/ID), ``result`` the run's other results."""

    def __init__(self, node, message, result=None):
        super().__init__(f"node \"{node}\": {message}")
        self.node = node
        self.pointer = f"/nodes/{node}"
        self.message = message
        self.result = result


class InputError(Error, ValueError):
    """A value given to a node input that the input cannot take."""

    def __init__(self, node, input, message):
        super().__init__(f"/nodes/{node}/inputs/{input}: {message}")
        self.node = node
        self.input = input
        self.pointer = f"/nodes/{node}/inputs/{input}"
