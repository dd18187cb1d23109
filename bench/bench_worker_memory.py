"""What a long-lived worker keeps from one trial to the next: the default scenario's trial is
built and simulated through its scan and GbH (to ``--until`` s), freed and garbage-collected,
``--trials`` times in one process, as an experiment worker does; prints the resident memory
(MB) after each, and how many GbH stage memos still hold a result.

Run:  .venv/bin/python bench/bench_worker_memory.py [--trials 4] [--until 1.3] [--no-memo]

``--no-memo`` computes every stage again (the memo's share of the growth). pydrake never frees a
Python LeafSystem, so each trial's systems stay; what they hold is what this measures.
"""

from __future__ import annotations

import argparse
import gc
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")


def rss_mb() -> float:
    """Resident set size of this process, MB."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=4)
    parser.add_argument("--until", type=float, default=1.3)
    parser.add_argument("--no-memo", action="store_true")
    args = parser.parse_args(argv)

    from pydrake.systems.analysis import Simulator

    import gbh_drake.systems.stage as stage
    from gbh_drake import REPO_ROOT
    from gbh_drake.scenario.loader import load_scenario
    from gbh_drake.trial import build_trial

    if args.no_memo:
        stage.LastResult.get = lambda self, key, compute: compute()
    scenario = load_scenario(REPO_ROOT / "scenarios" / "default.yaml")
    for i in range(args.trials):
        trial = build_trial(scenario)
        simulator = Simulator(trial.diagram)
        simulator.Initialize()
        simulator.AdvanceTo(args.until)
        del simulator, trial
        gc.collect()
        print(f"trial {i + 1}: {rss_mb():.0f} MB", flush=True)
    stages = [o for o in gc.get_objects() if isinstance(o, stage.AbstractStage)]
    holding = sum(o._last._result is not None for o in stages)
    print(f"{len(stages)} GbH stages alive, {holding} memos holding a result "
          f"({'no memo' if args.no_memo else 'memo'}; load {os.getloadavg()[0]:.1f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
