"""The report's plots, PNG and SVG: success as a heatmap of object x method (one per protocol)
and the failures by cause (stacked bars, one distinct colour per cause class)."""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import numpy as np

from gbh_drake.experiment.report.columns import UNKNOWN_CAUSE
from gbh_drake.experiment.report.facts import object_tags
from gbh_drake.experiment.report.inputs import ReportInput
from gbh_drake.experiment.report.tables import (
    cause_counts,
    groups,
    hangable,
    per_group,
    per_protocol,
    tally,
)

#: One colour per cause class, no two alike; related classes share a hue (reach: blues;
#: the collision rules: greens; IK / planner: reds; lift / carry: purples).
CAUSE_COLOURS = {
    "out of reach": "#1f77b4", "candidate set missed": "#9ecae1", "no structure": "#ff7f0e",
    "table clearance": "#2ca02c", "collision N_c": "#98df8a", "closing sweep": "#bcbd22",
    "rod clearance": "#31a354", "empty loop": "#006d2c",
    "no grasp found": "#8c564b", "IK": "#d62728", "planner": "#ff9896",
    "lift too low": "#9467bd", "touched down": "#e377c2", "slipped during carry": "#c5b0d5",
    "scan cut/partial": "#17becf",
    "error": "#7f7f7f", UNKNOWN_CAUSE: "#000000",
}

#: The heatmap's colour map (rate 0 to 1; perceptually uniform, readable in grey) and the
#: colour of a cell without trials.
RATE_MAP = "viridis"
NO_TRIALS = "#dddddd"


def _figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100)
    FigureCanvasAgg(fig)
    return fig


def _wrapped(text: str, width_in: float, fontsize: float) -> str:
    """``text`` broken into lines that fit ``width_in`` inches at ``fontsize`` points."""
    return "\n".join(textwrap.wrap(text, max(20, int(width_in * 72 / (0.55 * fontsize)))))


def _save(fig, path: Path) -> None:
    """``path`` (PNG) and the same with .svg, each written whole or not at all (the SVG without a
    date and with fixed ids: the same rows give the same file)."""
    import matplotlib

    for target in (path, path.with_suffix(".svg")):
        tmp = target.with_name(f".{target.stem}.{os.getpid()}.tmp{target.suffix}")
        with matplotlib.rc_context({"svg.hashsalt": "gbh"}):
            fig.savefig(tmp, metadata={"Date": None} if target.suffix == ".svg" else None)
        os.replace(tmp, target)


def success_grid(data: ReportInput) -> tuple[list[str], np.ndarray, np.ndarray]:
    """(row labels, successes, trials) of one protocol's heatmap: the objects with hangable
    parts together, then each object (controls marked), by method."""
    frame, tags = data.frame, object_tags(data.frame)
    parts = [("all hangable objects", hangable(frame))] + [
        (obj + (" (control)" if "control" in tags.get(obj, ()) else ""),
         frame[frame.object == obj]) for obj in data.objects]
    cells = [[tally(rows[rows.method == m]) for m in data.methods] for _, rows in parts]
    n = np.array([[c[0] for c in row] for row in cells], dtype=int).reshape(len(parts), -1)
    k = np.array([[c[1] for c in row] for row in cells], dtype=int).reshape(len(parts), -1)
    return [p[0] for p in parts], k, n


def plot_success(data: ReportInput, path: Path) -> None:
    """Success per object and method as a heatmap (cell text ``k/n``, colour the rate; a grey
    ``-`` without trials), one panel per protocol, the objects with hangable parts together
    in the first row (PNG and SVG)."""
    import matplotlib

    panels = [(one.protocols[0] if suffix else "", *success_grid(one))
              for suffix, one in per_protocol(data)]
    rows, cols = len(panels[0][1]), max(1, len(data.methods))
    width = max(6.0, 2.2 + len(panels) * (0.95 * cols + 0.3) + 1.0)
    height = 0.3 * rows + 2.4
    fig = _figure(width, height)
    colours = matplotlib.colormaps[RATE_MAP]
    axes = fig.subplots(1, len(panels), sharey=True, squeeze=False)[0]
    for ax, (protocol, labels, k, n) in zip(axes, panels, strict=True):
        rates = np.where(n > 0, k / np.maximum(n, 1), np.nan)
        ax.set_facecolor(NO_TRIALS)
        image = ax.imshow(np.ma.masked_invalid(rates), cmap=colours, vmin=0.0, vmax=1.0,
                          aspect="auto", interpolation="nearest")
        for (i, j), total in np.ndenumerate(n):
            dark = total and rates[i, j] < 0.55
            ax.text(j, i, f"{k[i, j]}/{total}" if total else "-", ha="center", va="center",
                    fontsize=7, color="white" if dark else "black",
                    fontweight="bold" if i == 0 else "normal")
        ax.axhline(0.5, color="white", linewidth=2)
        ax.set_xticks(range(n.shape[1]), data.methods, rotation=30, ha="right", fontsize=8)
        ax.set_yticks(range(len(labels)), labels, fontsize=8)
        ax.set_xlabel("method", fontsize=9)
        if protocol:
            ax.set_title(f"protocol {protocol}", fontsize=9)
    axes[0].set_ylabel("object", fontsize=9)
    left, right, bottom, top = 2.0 / width, 1 - 1.2 / width, 1.3 / height, 1 - 0.75 / height
    fig.subplots_adjust(left=left, right=right, bottom=bottom, top=top, wspace=0.08)
    bar = fig.colorbar(image, cax=fig.add_axes((1 - 0.95 / width, bottom, 0.15 / width,
                                                top - bottom)))
    bar.set_label("success rate (successes / trials)", fontsize=8)
    bar.ax.tick_params(labelsize=7)
    fig.suptitle(_wrapped(f"{data.name}: successes / trials per object and method (first row: "
                          "all objects with hangable parts)", width, 10), fontsize=10)
    _save(fig, path)


def plot_causes(data: ReportInput, path: Path) -> None:
    """The failed trials of the objects with hangable parts per method (and protocol), stacked
    by cause (the classes with at least one trial, one colour each), PNG and SVG."""
    counts = cause_counts(data)
    counts = counts[counts.sum(axis=1) > 0]
    labels = [g[0] for g in groups(data)]
    width = max(6.0, 1.0 * len(labels) + 3.4)
    fig = _figure(width, 4.6)
    ax = fig.add_subplot(1, 1, 1)
    xs = np.arange(len(labels))
    bottom = np.zeros(len(labels))
    top = max(1, counts.sum(axis=0).max() if len(counts) else 1)
    for cause, values in counts.iterrows():
        ax.bar(xs, values.to_numpy(), bottom=bottom, width=0.6, label=cause,
               color=CAUSE_COLOURS[cause], edgecolor="white", linewidth=0.5)
        for x, v, b in zip(xs, values, bottom, strict=True):
            if v >= 0.05 * top:  # a count where it fits
                ax.text(x, b + v / 2, str(v), ha="center", va="center", fontsize=7)
        bottom += values.to_numpy()
    totals = {label: len(rows) for label, rows in per_group(data, hangable(data.frame))}
    ax.set_xticks(xs, [f"{g}\n({totals[g]} trials)" for g in labels], fontsize=7,
                  rotation=30 if len(labels) > 6 else 0, ha="right" if len(labels) > 6 else
                  "center")
    ax.set_xlabel("method" + (" (protocol)" if len(data.protocols) > 1 else ""), fontsize=9)
    ax.set_ylabel("failed trials", fontsize=9)
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.set_title(_wrapped(f"{data.name}: failures by cause (objects with hangable parts)",
                          width - 2.4, 10), fontsize=10)
    if len(counts):
        ax.legend(title="cause", fontsize=7, title_fontsize=8, loc="center left",
                  bbox_to_anchor=(1.01, 0.5), frameon=False, reverse=True)
    else:
        ax.text(0.5, 0.5, "no failures", transform=ax.transAxes, ha="center")
    ax.grid(axis="y", alpha=0.3)
    ax.set_axisbelow(True)
    fig.tight_layout()
    _save(fig, path)
