"""Counts in words: ``1 hanging structure``, ``2 hanging structures``."""

from __future__ import annotations


def counted(n: int, noun: str, plural: str = "") -> str:
    """``n`` and ``noun``, plural unless ``n`` is 1 (``plural``: an irregular one, default
    ``noun`` + ``s``)."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"
