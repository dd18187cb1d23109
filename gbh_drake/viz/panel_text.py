"""Lines of text in Meshcat's control panel (the studio's explanations and verdicts).

Drake's Meshcat draws no text, but a button's label spans the panel's width: each line is a
button that nothing reads (pressing it does nothing). Lines are wrapped to :data:`WIDTH`
characters (the panel is 245 px wide; drag its edge to widen it) and start with
:data:`MARK`, so that no line can take the name of a real control.
"""

from __future__ import annotations

import textwrap

from pydrake.geometry import Meshcat

#: Characters per line.
WIDTH = 40
#: What every line starts with.
MARK = "\u00b7 "
#: Appended (repeated) to a line that equals an earlier one: control names are unique.
_PAD = "\u200b"
#: Quotes and backslashes as typographic look-alikes: Meshcat's page puts a button's name in a
#: quoted JavaScript string.
_QUOTES = str.maketrans({"'": "\u2019", '"': "\u201d", "\\": "/"})


class PanelText:
    """The lines shown at the end of ``meshcat``'s control panel (replaced by :meth:`show`)."""

    def __init__(self, meshcat: Meshcat):
        self._meshcat = meshcat
        self._names: list[str] = []

    def show(self, lines: list[str]) -> None:
        """Replaces the lines shown by ``lines`` (each wrapped to :data:`WIDTH`)."""
        self.clear()
        for line in wrapped(lines):
            name = MARK + line.translate(_QUOTES)
            while name in self._names:
                name += _PAD
            self._meshcat.AddButton(name)
            self._names.append(name)

    def clear(self) -> None:
        """Removes the lines shown."""
        for name in self._names:
            self._meshcat.DeleteButton(name, strict=False)
        self._names = []

    def forget(self) -> None:
        """Forgets the lines (their controls were deleted by someone else)."""
        self._names = []

    @property
    def lines(self) -> list[str]:
        """The lines shown, as wrapped."""
        return [name[len(MARK):].rstrip(_PAD) for name in self._names]


def wrapped(lines: list[str], width: int = WIDTH) -> list[str]:
    """``lines`` wrapped to ``width`` characters, continuation lines indented."""
    out: list[str] = []
    for line in lines:
        out += textwrap.wrap(line, width, subsequent_indent="  ", break_on_hyphens=False) or [""]
    return [line for line in out if line]
