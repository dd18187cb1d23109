"""The station's model-instance names, defined once (pydrake-free).

The scenario's directive checks and the station both use these names: the arm, the hook gripper
and the table a scenario's directives must add, and the hand's actuated joints.
"""

ARM = "panda"
GRIPPER = "hook_gripper"
TABLE = "table"
HAND_ACTUATORS = ("straight_finger_joint", "l_finger_joint", "bar_joint")
