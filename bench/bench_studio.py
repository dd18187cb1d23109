"""How responsive the studio is on the default scenario's mug (``gbh studio``'s page, driven
in-process): Place (build and settle), Scan, Detect after the scan, each move of the rank slider
(the redraw, then the planner's answer apart), and Execute's real-time factor (simulated seconds
over wall seconds, the live Meshcat drawing it, no real-time pacing) beside ``gbh run``'s trial
of the same scenario without Meshcat. Wall and CPU seconds (the machine is shared).

Usage: ``.venv/bin/python bench/bench_studio.py [--views 10] [--ranks 5]``.
"""

from __future__ import annotations

import argparse
import os


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views", type=int, default=10)
    parser.add_argument("--ranks", type=int, default=5, help="rank slider moves timed")
    args = parser.parse_args()

    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.scenario import load_scenario
    from gbh_drake.studio.choices import object_choices
    from gbh_drake.studio.controls import Studio
    from gbh_drake.studio.session import Session
    from gbh_drake.trial import build_trial, simulate_trial
    from gbh_drake.viz.meshcat_server import local_meshcat

    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores")
    base = load_scenario(SCENARIOS_DIR / "default.yaml",
                         overrides=f"{{scan: {{num_views: {args.views}}}}}")
    meshcat = local_meshcat()
    studio = Studio(Session(base, object_choices(base), meshcat=meshcat), meshcat,
                    say=lambda _: None)
    studio.scan()
    studio.detect()
    t = studio.timings
    print(f"place  {t['place']}\nscan   {t['scan']}\ndetect {t['detect']}  (after the scan)")
    offered = [o for o in studio.session.detection.offered if not o.rule]
    for rank in range(1, min(args.ranks + 1, len(offered))):
        studio.select(rank)
        print(f"rank {rank + 1}: redraw {t['grasp']}; planner's answer {t['plan']}")
    studio.select(0)
    studio.execute()
    record = studio.session.record
    simulated = record.sim_time - studio.session.execute_from
    wall = record.timings["simulate"]
    print(f"execute: {simulated:.2f} s simulated in {wall:.2f} s: real-time factor "
          f"{simulated / wall:.3f} ({record.outcome})")
    _, run = simulate_trial(build_trial(base))
    print(f"gbh run's trial (no Meshcat): {run.sim_time:.2f} s simulated in "
          f"{run.timings['simulate']:.2f} s: real-time factor "
          f"{run.sim_time / run.timings['simulate']:.3f} ({run.outcome})")


if __name__ == "__main__":
    main()
