"""The README's example run, from a real run: what ``gbh run scenarios/default.yaml`` prints.

Run:  .venv/bin/python tools/readme_run_output.py            # rewrite the block in README.md
      .venv/bin/python tools/readme_run_output.py --check    # exit 1 when the block is stale

The block sits in README.md between ``<!-- run-output -->`` and ``<!-- end run-output -->``.
The run is made in a temporary folder (the repository's ``scenarios/`` linked into it), so the
outputs go where a user's would, under the current folder (``output/default/``), and nothing
is written into the checkout but the README. ``gbh run`` prints full paths; the run's folder and
the checkout's are both shown as :data:`CHECKOUT`, where a user in a checkout would run it (the
folder differs from one clone to the next).
``tests/docs/test_readme_run.py`` runs it and compares (:func:`same_run`): wall times and
real-time factors aside (:func:`normalised`), they are the machine's; counts exactly; measured
decimals (simulated seconds, the clearance, the score) within :data:`DECIMAL_TOLERANCE`, the
last digits of the physics differ from one processor to another (11.69 s simulated on one
machine, 11.71 on another; the seeded trial is the same).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
START, END = "<!-- run-output -->", "<!-- end run-output -->"
#: What the block shows a user typing (dev.sh passes its arguments to ``gbh run``).
COMMAND = "./dev.sh run scenarios/default.yaml"
#: How the block writes the checkout's folder.
CHECKOUT = "/path/to/gbh_drake"

#: The machine's figures in a run's text: the wall time and the real-time factor of the
#: simulation, and every stage's time.
_WALL = re.compile(r"in [0-9.]+ s wall \([0-9.]+x real time\)")
_TIMINGS = re.compile(r"^(\s*timings: ).*$", re.MULTILINE)
#: A number with a decimal point in a run's text.
_DECIMAL = re.compile(r"\d+\.\d+")
#: Relative difference allowed between two runs' decimals: a processor's floating point moves
#: the physics' last digits (the default run's clearance 5.7 or 5.8 cm, 11.69 or 11.71 s).
DECIMAL_TOLERANCE = 0.02


def fresh_run() -> str:
    """What ``gbh run scenarios/default.yaml`` prints on stdout, run from a temporary folder
    that holds a link to the repository's ``scenarios/``."""
    with tempfile.TemporaryDirectory() as folder:
        os.symlink(ROOT / "scenarios", Path(folder) / "scenarios")
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)}
        done = subprocess.run([sys.executable, "-m", "gbh_drake.cli", "run", "scenarios/default.yaml"],
                              cwd=folder, env=env, capture_output=True, text=True, check=False)
        here = str(Path(folder).resolve())
    if done.returncode != 0:
        raise RuntimeError(f"gbh run exited {done.returncode}:\n{done.stderr}")
    # The run's folder stands for the checkout, where a user runs it.
    return done.stdout.rstrip("\n").replace(here, CHECKOUT).replace(str(ROOT.resolve()), CHECKOUT)


def block(output: str) -> str:
    """The README's block: the command and what it printed, as a console code block."""
    return f"{START}\n```console\n$ {COMMAND}\n{output}\n```\n{END}"


def readme_output(text: str) -> str:
    """The run's output as the README's block holds it (without the command line)."""
    inside = text[text.index(START) + len(START):text.index(END)]
    lines = inside.strip("\n").splitlines()
    return "\n".join(lines[2:-1])  # less the fence, the command and the closing fence


def normalised(output: str) -> str:
    """``output`` with the machine's figures (wall times, real-time factors, stage times)
    replaced by placeholders."""
    output = _WALL.sub("in <wall> s wall (<rate>x real time)", output)
    return _TIMINGS.sub(r"\1<timings>", output)


def same_run(stated: str, fresh: str) -> bool:
    """Whether two runs' texts are the same run: equal once :func:`normalised`, but for their
    decimals, each within :data:`DECIMAL_TOLERANCE` (relative) of the other's."""
    a, b = normalised(stated), normalised(fresh)
    if _DECIMAL.sub("<d>", a) != _DECIMAL.sub("<d>", b):
        return False
    return all(abs(float(x) - float(y)) <= DECIMAL_TOLERANCE * max(abs(float(x)), abs(float(y)))
               for x, y in zip(_DECIMAL.findall(a), _DECIMAL.findall(b), strict=True))


def with_block(text: str, output: str) -> str:
    """``text`` (the README) with its block replaced by one holding ``output``."""
    start, end = text.index(START), text.index(END) + len(END)
    return text[:start] + block(output) + text[end:]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="only compare (same_run); exit 1 when the README is stale")
    args = parser.parse_args(argv)
    output = fresh_run()
    text = README.read_text()
    if args.check:
        stale = not same_run(readme_output(text), output)
        print("README.md's run output is " + ("stale" if stale else "current"))
        return int(stale)
    README.write_text(with_block(text, output))
    print(f"wrote the run's output into {README}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
