"""The ``HandDriver`` system: the Franka Hand's force-limited finger drive and the bar's servo.

Franka's hand moves both fingers together at a limited speed and, once they are blocked,
squeezes with a set force (70 N continuous, 140 N peak). Here each finger joint is a
position-controlled actuator of the plant (implicit PD with stiffness ``kp``, effort limited to
``max_force`` by the plant). The driver turns a command ``[q_target, force, bar_angle]`` into
the actuators' desired state:

* a set point ``q_ref`` (discrete state, one per finger) moves toward ``q_target`` at ``speed``;
* the desired position is ``q_ref`` kept within ``force / kp`` of the measured finger position,
  so a finger that is blocked (by the material, or by the bar's tip on the straight rod) pushes
  with ``force`` and no more, whatever ``q_target`` is;
* the bar's joint goes to ``bar_angle`` (0: deployed, the hook; -pi/2: folded onto the L rod).
"""

from __future__ import annotations

import math

from pydrake.systems.framework import BasicVector, LeafSystem

from gbh_drake.scenario.schema import HandConfig

#: Indices of the command vector.
Q_TARGET, FORCE, BAR_ANGLE = 0, 1, 2


class HandDriver(LeafSystem):
    """Force-limited finger drive of the hook gripper (see the module docstring).

    .. pydrake_system::

        name: HandDriver
        input_ports:
        - command
        - state
        output_ports:
        - desired_state

    ``command`` (3): finger target q (m, each finger's joint position, half the opening), grasp
    force (N, clipped to ``config.max_force``), bar angle (rad). ``state`` (6): the gripper's
    measured [q_straight, q_l, theta_bar, v_straight, v_l, omega_bar] (m, rad, m/s, rad/s).
    ``desired_state`` (6): the same layout, for the plant's desired-state input of the gripper.
    """

    def __init__(self, config: HandConfig, time_step: float = 0.004):
        """``time_step`` (s): how often the set point moves (a few plant steps: the stiff drive
        smooths the steps of ``speed * time_step``)."""
        super().__init__()
        self._config = config
        self._dt = float(time_step)
        self._command = self.DeclareVectorInputPort("command", 3)
        self._state = self.DeclareVectorInputPort("state", 6)
        self._q_ref = self.DeclareDiscreteState(2)
        self.DeclarePeriodicDiscreteUpdateEvent(self._dt, 0.0, self._move_set_point)
        self.DeclareInitializationDiscreteUpdateEvent(self._start_at_measured)
        self.DeclareVectorOutputPort("desired_state", 6, self._calc_desired_state)

    def _start_at_measured(self, context, discrete_state) -> None:
        discrete_state.set_value(self._q_ref, self._state.Eval(context)[:2])

    def _move_set_point(self, context, discrete_state) -> None:
        q_ref = context.get_discrete_state(self._q_ref).get_value()
        q_target = float(self._command.Eval(context)[Q_TARGET])
        step = self._config.speed * self._dt
        discrete_state.set_value(self._q_ref, [min(max(q_target, q - step), q + step)
                                               for q in q_ref])

    def _calc_desired_state(self, context, output: BasicVector) -> None:
        q_target, force, bar = (float(c) for c in self._command.Eval(context))
        x = self._state.Eval(context)
        reach = min(max(force, 0.0), self._config.max_force) / self._config.kp
        q_d, v_d = [], []
        for q_ref, q in zip(context.get_discrete_state(self._q_ref).get_value(), x[:2],
                            strict=True):
            desired = min(max(q_ref, q - reach), q + reach)
            # A moving set point asks for the drive's speed; blocked or arrived fingers for none.
            moving = abs(q_ref - q_target) > 1e-9 and desired == q_ref
            q_d.append(desired)
            v_d.append(math.copysign(self._config.speed, q_target - q_ref) if moving else 0.0)
        output.SetFromVector([*q_d, bar, *v_d, 0.0])
