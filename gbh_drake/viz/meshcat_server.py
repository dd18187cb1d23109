"""The project's Meshcat server: listening on the loopback only.

Drake's ``Meshcat()`` listens on all interfaces by default; a simulation has no business being
reachable from other machines, so every Meshcat of gbh_drake comes from :func:`local_meshcat`.
"""

from pydrake.geometry import Meshcat, MeshcatParams


def local_meshcat(port: int | None = None) -> Meshcat:
    """A Meshcat server on ``localhost`` (the first free port from 7000, or ``port``)."""
    params = MeshcatParams(host="localhost")
    if port is not None:
        params.port = port
    return Meshcat(params)
