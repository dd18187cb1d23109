"""What touches the object, and how it moves, while a pick sets it down (LOWER, RELEASE, RETREAT).

    python tools/setdown_trace.py [SCENARIO.yaml] [--set YAML ...] [--every 0.02]

Runs the scenario's trial (real Drake, as ``gbh run`` does, without the replay) and from the
LOWER phase on prints, every ``--every`` simulated seconds: the machine's mode, the object's
position p_WO (m) and roll-pitch-yaw (deg), its axes x_O and z_O in W, the hand's load (N, W:
the force the flange exerts on the hand, ``hook_gripper.load``) and every contact on the object
by body (the force on the object, N, W, and where it acts, m, W). It stops one second after
the machine has finished and prints the machine's set-down notes. A diagnostic: it writes
nothing.
"""

from __future__ import annotations

import argparse

import numpy as np
from pydrake.math import RollPitchYaw
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator

from gbh_drake import SCENARIOS_DIR
from gbh_drake.messages import Mode
from gbh_drake.scenario.loader import load_scenario
from gbh_drake.trial import build_trial, trial_duration

#: The modes traced (the set-down's).
TRACED = (Mode.LOWER, Mode.RELEASE, Mode.RETREAT, Mode.DONE)


def contacts_on(plant, inspector, results, body) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(other body's name, force on ``body`` (N, W), where it acts (m, W)) for each contact of
    ``body`` in ``results`` (point pairs and hydroelastic surfaces)."""
    out = []
    for i in range(results.num_point_pair_contacts()):
        c = results.point_pair_contact_info(i)
        a, b = c.bodyA_index(), c.bodyB_index()
        if body.index() in (a, b):  # contact_force is on B
            sign = 1.0 if b == body.index() else -1.0
            other = a if b == body.index() else b
            out.append((plant.get_body(other).name(), sign * c.contact_force(),
                        c.contact_point()))
    for i in range(results.num_hydroelastic_contacts()):
        c = results.hydroelastic_contact_info(i)
        s = c.contact_surface()
        m, n = (plant.GetBodyFromFrameId(inspector.GetFrameId(g)) for g in (s.id_M(), s.id_N()))
        if body.index() in (m.index(), n.index()):  # F_Ac_W is on M's body
            sign = 1.0 if m.index() == body.index() else -1.0
            other = n if m.index() == body.index() else m
            out.append((other.name(), sign * c.F_Ac_W().translational(), s.centroid()))
    return out


def trace(scenario, every: float) -> None:
    """Prints the set-down of ``scenario``'s trial (see the module docstring)."""
    trial = build_trial(scenario)
    simulator = Simulator(trial.diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    simulator.Initialize()
    root = simulator.get_context()
    station, plant = trial.station, trial.station.plant
    body = station.object_body()
    status_port = trial.pick.GetOutputPort("status")
    end = trial_duration(trial)
    while root.get_time() < end:
        simulator.AdvanceTo(root.get_time() + every)
        status = status_port.Eval(trial.pick.GetMyContextFromRoot(root))
        if status.mode not in TRACED:
            if status.finished:
                break
            continue
        station_context = station.GetMyContextFromRoot(root)
        X_WO = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(root), body)
        R = X_WO.rotation().matrix()
        load = station.GetOutputPort("hook_gripper.load").Eval(station_context)
        inspector = station.GetOutputPort("query_object").Eval(station_context).inspector()
        results = station.GetOutputPort("contact_results").Eval(station_context)
        touching = "; ".join(f"{name} F {np.round(f, 2)} at {np.round(p, 3)}"
                             for name, f, p in contacts_on(plant, inspector, results, body))
        rpy = np.degrees(RollPitchYaw(X_WO.rotation()).vector())
        print(f"t {root.get_time():6.2f} {status.mode.value:8s} p_WO {np.round(X_WO.translation(), 3)}"
              f" rpy {np.round(rpy)} x_O {np.round(R[:, 0], 2)} z_O {np.round(R[:, 2], 2)}"
              f" load {np.round(load, 1)} | {touching}")
        if status.finished and root.get_time() > status.phase_start[status.mode.value] + 1.0:
            break
    for note in status.set_down_notes:  # what the machine sensed and did
        print(f"note: {note}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", nargs="?", default=str(SCENARIOS_DIR / "default.yaml"))
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="YAML", help="YAML text applied over the file (repeatable)")
    parser.add_argument("--every", type=float, default=0.02, help="simulated s between lines")
    args = parser.parse_args()
    trace(load_scenario(args.scenario, overrides=args.overrides), args.every)


if __name__ == "__main__":
    main()
