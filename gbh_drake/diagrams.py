"""Graphviz renderings of Drake diagrams (``diagrams/``)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path


def write_diagram(diagram, out_dir: Path, name: str, max_depth: int = 1) -> list[Path]:
    """Writes ``<name>.dot`` and, when Graphviz's ``dot`` is installed, ``<name>.svg``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    dot_path = out_dir / f"{name}.dot"
    dot_path.write_text(diagram.GetGraphvizString(max_depth=max_depth))
    written = [dot_path]
    dot = shutil.which("dot")
    if dot:
        svg_path = out_dir / f"{name}.svg"
        subprocess.run([dot, "-Tsvg", str(dot_path), "-o", str(svg_path)], check=True)
        written.append(svg_path)
    return written
