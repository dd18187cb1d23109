"""Reading a saved Meshcat page (a replay, ``gbh grasps --html``) the way a browser does: its
commands, its animation tracks, what it would fetch."""

from __future__ import annotations

import base64
import re

import msgpack

_DATA = re.compile(r'fetch\("data:application/octet-binary;base64,([^"]+)"\)')
#: Attributes that make a browser fetch something.
_FETCHES = re.compile(r"<(?:script|img|link|iframe|source|video|audio)\b[^>]*\b(?:src|href)"
                      r"""\s*=\s*["']?([^"'\s>]+)""", re.IGNORECASE)


def commands(page: str) -> list[dict]:
    """The Meshcat commands the page hands its viewer, in order."""
    return [msgpack.unpackb(base64.b64decode(m)) for m in _DATA.findall(page)]


def tracks(page: str) -> dict[str, dict[str, list[dict]]]:
    """The page's animation: {path: {track name (``.position``, ``.visible``): keys}}, each key
    ``{"time": frame, "value": ...}``."""
    found: dict[str, dict[str, list[dict]]] = {}
    for command in commands(page):
        if command["type"] == "set_animation":
            for animation in command["animations"]:
                found[animation["path"]] = {t["name"]: t["keys"]
                                            for t in animation["clip"]["tracks"]}
    return found


def fetched(page: str) -> list[str]:
    """What the page's tags would fetch (src, href), data: URIs and in-page anchors left out;
    the scripts' own ``fetch`` calls are all of data: URIs (``_DATA``) or listed here."""
    links = [u for u in _FETCHES.findall(page) if not u.startswith(("data:", "#"))]
    calls = re.findall(r'fetch\("([^"]{0,40})', page)
    return links + [u for u in calls if not u.startswith("data:")]
