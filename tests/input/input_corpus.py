"""The bad-input corpus: scenario files a new user might write, each with its exact outcome.

Each :class:`Case` is a scenario text (plus optional ``--set`` overrides and extra files) and
what ``gbh run`` must say about it: exit code 2 and one line

    gbh: invalid scenario: <file>[ (overrides)]: <field> (line N): <problem>

where ``field`` and ``line`` are given (``line=None``: no line in the message; ``field=""``: a
problem of the file as a whole, ``<file>: line N, column C: <problem>``) and ``problem``
contains ``expect``. ``test_corpus.py`` runs every case through the real command line.
Generated cases (every numeric field NaN and infinite, every rule out of range, every field
of the wrong type) are in ``tests/scenario/test_every_field.py``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from gbh_drake.modeling.directives import REMOTE_PACKAGES

#: A package Drake would download on first use (refused by validation; never fetched here).
REMOTE = REMOTE_PACKAGES[0]

#: A valid mesh (a 2 cm cube) for cases that need one.
CUBE_OBJ = "\n".join(
    [f"v {x} {y} {z}" for x in (0, 0.02) for y in (0, 0.02) for z in (0, 0.02)]
    + ["f 1 3 4", "f 1 4 2", "f 5 6 8", "f 5 8 7", "f 1 2 6", "f 1 6 5",
       "f 3 7 8", "f 3 8 4", "f 1 5 7", "f 1 7 3", "f 2 4 8", "f 2 8 6"]) + "\n"

#: The default directives with one line changed (for directive cases).
ARM = "- add_model: {name: panda, file: 'package://gbh_drake/panda_arm.urdf'}\n"
WELD_ARM = "- add_weld: {parent: world, child: panda::panda_link0}\n"
GRIPPER = "- add_model: {name: hook_gripper, file: 'package://gbh_drake/hook_gripper.sdf'}\n"
WELD_GRIPPER = "- add_weld: {parent: panda::panda_link8, child: hook_gripper::panda_hand}\n"
TABLE = "- add_model: {name: table, file: 'package://gbh_drake/table.sdf'}\n"
WELD_TABLE = ("- add_weld: {parent: world, child: table::table_top, "
              "X_PC: {translation: [0.35, 0, 0]}}\n")
DIRECTIVES = "directives:\n" + ARM + WELD_ARM + GRIPPER + WELD_GRIPPER + TABLE + WELD_TABLE


@dataclass
class Case:
    id: str
    text: str | bytes
    field: str
    line: int | None
    expect: str
    overrides: tuple[str, ...] = ()
    origin: str = ""
    """Suffix of the file name in the message: "" or " (overrides)" / " (overrides 2 of 2)"."""
    files: dict[str, str | bytes] = field(default_factory=dict)
    """Other files written beside the scenario."""


def write_case(case: Case, folder, substitutions: dict[str, str]):
    """Writes the case's files and its text (``bad.yaml``) into ``folder``, each key of
    ``substitutions`` in a text replaced by its value; returns the text's path."""
    def data(content):
        if isinstance(content, bytes):
            return content
        for key, value in substitutions.items():
            content = content.replace(key, value)
        return content.encode()
    for name, content in case.files.items():
        (folder / name).write_bytes(data(content))
    path = folder / "bad.yaml"
    path.write_bytes(data(case.text))
    return path


def check_refusal(case: Case, main, argv: list[str], capsys, prefix: str, nothing: Path):
    """Runs ``main(argv + the case's --set overrides)`` and checks the refusal: exit 2, one line
    on stderr starting with ``prefix``, the case's words in its problem
    (a column may follow the line), no traceback, nothing on stdout and no ``nothing`` folder."""
    for text in case.overrides:
        argv = [*argv, "--set", text]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(prefix), f"\n{lines[0]}\n{prefix}"
    problem = lines[0][len(prefix):]
    if not case.field and case.line:  # the column may follow
        assert re.match(r"(, column \d+)?: ", problem), problem
    assert case.expect in problem, f"{case.expect!r} not in {problem!r}"
    assert "Traceback" not in err and out == ""
    assert not nothing.exists()  # nothing written


def _c(id, text, field, line, expect, **kw) -> Case:
    return Case(id, text, field, line, expect, **kw)


CASES: list[Case] = [
    # ---- the file as a whole ---------------------------------------------------------------
    _c("utf16_bom", "seed: 1\n".encode("utf-16"), "", None, "is UTF-16 text; save it as UTF-8"),
    _c("utf16_no_bom", "seed: 1\n".encode("utf-16-le"), "", None, "looks like UTF-16"),
    _c("utf32", "seed: 1\n".encode("utf-32"), "", None, "is UTF-32 text"),
    _c("latin1", "# caf\xe9\nseed: 1\n".encode("latin-1"), "", 1, "is not UTF-8 text (byte 0xe9)"),
    _c("binary", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "", 3, "NUL byte: not a text file"),
    _c("nul_in_text", b"seed: 1\nobject: {}\x00\n", "", 2, "NUL byte"),
    _c("too_large", "# " + "x" * 1_000_100 + "\n", "", None, "a scenario file has at most"),
    _c("syntax_unclosed", "seed: 1\nobject: [\n", "", 3, "not valid YAML"),
    _c("syntax_tab", "seed: 1\n\tobject: {}\n", "", 2, "not valid YAML"),
    _c("syntax_bad_indent", "object:\n  name: mug_classic\n scale: 1\n", "", 3, "not valid YAML"),
    _c("two_documents", "seed: 1\n---\nseed: 2\n", "", 2, "expected a single document"),
    _c("nested_flow", "seed: " + "[" * 60 + "]" * 60 + "\n", "", None, "nested deeper than 40"),
    _c("alias_bomb", "".join(f"{k}: &{k} [{', '.join([f'*{p}'] * 9 if p else ['1'] * 9)}]\n"
                             for p, k in zip(["", "a", "b", "c", "d", "e"],
                                             ["a", "b", "c", "d", "e", "f"], strict=True)),
       "", None, "expands to more than 100000 values"),
    _c("root_list", "- seed: 1\n", "", 1, "a scenario is a mapping of fields"),
    _c("root_scalar", "hello\n", "", 1, "a scenario is a mapping of fields"),
    _c("root_number", "42\n", "", 1, "a scenario is a mapping of fields"),
    _c("key_not_a_name", "1: 2\n", "1", 1, "not a field name"),
    _c("unknown_top", "sed: 3\n", "sed", 1, "unknown field (did you mean 'seed'?"),
    _c("source_path", "source_path: /tmp/x.yaml\n", "source_path", 1, "set by the loader"),
    # ---- duplicate keys (Drake's loader would keep the last) ----------------------------------
    _c("dup_root", "seed: 0\nseed: 1\n", "seed", 2, "given twice (first at line 1)"),
    _c("dup_nested", "object:\n  name: mug_classic\n  scale: 1\n  name: kettle\n", "object.name",
       4, "given twice (first at line 2)"),
    _c("dup_flow", "robot: {gripper_open: true, gripper_open: false}\n", "robot.gripper_open", 1,
       "given twice"),
    _c("dup_in_list", "cameras:\n- name: a\n  fps: 5\n  fps: 6\n", "cameras[0].fps", 4,
       "given twice (first at line 3)"),
    _c("dup_section", "scan:\n  num_views: 1\nseed: 2\nscan:\n  width: 320\n", "scan", 4,
       "given twice (first at line 1)"),
    # ---- types ------------------------------------------------------------------------------
    _c("seed_word", "seed: seven\n", "seed", 1, "expected an integer, got 'seven'"),
    _c("seed_fraction", "seed: 1.5\n", "seed", 1, "expected an integer"),
    _c("seed_bool", "seed: true\n", "seed", 1, "expected an integer"),
    _c("seed_list", "seed: [1]\n", "seed", 1, "expected an integer, got a list"),
    _c("int_exponent", "gbh:\n  n_points: 1e4\n", "gbh.n_points", 2,
       "expected an integer (whole number, digits only), got '1e4'"),
    _c("task_number", "task: 3\n", "task", 1, "expected a string, got '3'"),
    _c("task_bool", "task: yes\n", "task", 1, "expected a string"),
    _c("bool_word", "robot:\n  gripper_open: maybe\n", "robot.gripper_open", 2,
       "expected true or false, got 'maybe'"),
    _c("object_list", "object: [mug_classic]\n", "object", 1,
       "expected a mapping of ObjectConfig fields"),
    _c("object_string", "object: mug_classic\n", "object", 1,
       "expected a mapping of ObjectConfig fields (name, set, mesh"),
    _c("scale_list", "object:\n  scale: [1, 2]\n", "object.scale", 2,
       "expected a number, got a list"),
    _c("scan_target_string", "scan_target: '123'\n", "scan_target", 1,
       "expected a list, got '123'"),
    _c("scan_target_number", "scan_target: 5\n", "scan_target", 1, "expected a list, got '5'"),
    _c("q_home_string", "robot:\n  q_home: '1234567'\n", "robot.q_home", 2,
       "expected a list, got '1234567'"),
    _c("q_home_word_item", "robot:\n  q_home: [0, -0.3, zero, -2.2, 0, 1.9, 0.78]\n",
       "robot.q_home[2]", 2, "expected a number, got 'zero'"),
    _c("hand_number", "robot:\n  hand: 5\n", "robot.hand", 2, "expected a mapping of HandConfig"),
    _c("cameras_mapping", "cameras:\n  name: c\n", "cameras", 2, "expected a list, got a mapping"),
    _c("camera_width_word", "cameras:\n- name: c\n  width: wide\n", "cameras[0].width", 3,
       "expected an integer, got 'wide'"),
    _c("unknown_nested", "object:\n  nmae: mug_classic\n", "object.nmae", 2,
       "unknown field (did you mean 'name'?"),
    _c("unknown_drake", "plant_config:\n  time_stepp: 0.001\n", "plant_config.time_stepp", 2,
       "unknown field (did you mean 'time_step'?"),
    _c("unknown_in_list", "cameras:\n- name: c\n  fsp: 10\n", "cameras[0].fsp", 3,
       "did you mean 'fps'?"),
    _c("unknown_directive", "directives:\n- add_modle: {name: x, file: y}\n",
       "directives[0].add_modle", 2, "unknown field (did you mean 'add_model'?"),
    _c("unknown_tag", "object:\n  pose:\n    rotation: !Foo {}\n", "object.pose.rotation", 3,
       "unknown tag !Foo (allowed: !Identity, !Rpy, !AngleAxis, !Uniform)"),
    _c("scalar_tag_for_vector", "object:\n  pose:\n    translation: !Uniform {min: 0, max: 1}\n",
       "object.pose.translation", 3, "unknown tag !Uniform (allowed: a list of numbers"),
    _c("translation_mapping", "object:\n  pose:\n    translation: {x: 1}\n",
       "object.pose.translation", 3, "expected a list of numbers, got a mapping"),
    _c("rgba_out_of_range",
       "visualization:\n  default_illustration_color: {rgba: [2, 0, 0, 1]}\n",
       "visualization.default_illustration_color.rgba", 2, "Rgba values must be within the range"),
    _c("random_pose_scalar", "object:\n  random_pose: 3\n", "object.random_pose", 2,
       "expected a mapping of RandomRestingPose"),
    # ---- numbers that are not finite ----------------------------------------------------------
    _c("huge_integer_for_number", "settle_time: 1" + "0" * 400 + "\n", "settle_time", 1,
       "expected a number"),
    _c("huge_exponent", "settle_time: 1e400\n", "settle_time", 1, "must be a finite number"),
    _c("nan_word", "settle_time: nan\n", "settle_time", 1, "must be a finite number, got nan"),
    _c("inf_translation", "object:\n  pose:\n    translation: [.inf, 0, 0]\n",
       "object.pose.translation[0]", 3, "must be a finite number, got inf"),
    _c("nan_rpy", "object:\n  pose:\n    rotation: !Rpy {deg: [0, .nan, 0]}\n",
       "object.pose.rotation.deg[1]", 3, "must be a finite number"),
    _c("nan_uniform", "object:\n  pose:\n    translation: !UniformVector {min: [.nan, 0, 0], "
                      "max: [0.6, 0, 0]}\n", "object.pose.translation.min[0]", 3,
       "must be a finite number"),
    _c("nan_q_home", "robot:\n  q_home: [0, -0.3, 0, -2.2, 0, .nan, 0.78]\n", "robot.q_home[5]",
       2, "must be a finite number"),
    _c("inf_camera_fps", "cameras:\n- name: c\n  fps: .inf\n", "cameras[0].fps", 3,
       "must be a finite number"),
    _c("nan_directive_pose", "directives:\n" + ARM + WELD_ARM + GRIPPER + WELD_GRIPPER + TABLE
       + "- add_weld: {parent: world, child: table::table_top, X_PC: {translation: [.nan, 0, 0]}}"
       "\n", "directives[5].add_weld.X_PC.translation[0]", 7, "must be a finite number"),
    _c("nan_angle_axis", "object:\n  pose:\n    rotation: !AngleAxis {angle_deg: .nan, "
                         "axis: [0, 0, 1]}\n", "object.pose.rotation.angle_deg", 3,
       "must be a finite number"),
    # ---- ranges and lengths -------------------------------------------------------------------
    _c("seed_negative", "seed: -1\n", "seed", 1, "must be an integer in [0, 18446744073709551615]"),
    _c("seed_too_big", "seed: 18446744073709551616\n", "seed", 1, "unsigned 64-bit"),
    _c("q_home_short", "robot:\n  q_home: [0, 0, 0]\n", "robot.q_home", 2,
       "needs 7 joint positions (rad, panda_joint1..7), got 3"),
    _c("q_home_limits", "robot:\n  q_home: [0, -0.3, 0, 0.5, 0, 1.9, 0.78]\n", "robot.q_home[3]",
       2, "0.5 rad is outside panda_joint4's limits [-3.0718, -0.0698] rad"),
    _c("gains_short", "robot:\n  arm_kp: [1, 2]\n", "robot.arm_kp", 2, "needs 7 gains"),
    _c("gain_negative", "robot:\n  arm_kd: [200, 200, 200, -200, 60, 60, 60]\n",
       "robot.arm_kd[3]", 2, "must be in (0, 100000] N m s/rad, got -200"),
    _c("hand_kp_negative", "robot:\n  hand: {kp: -3}\n", "robot.hand.kp", 2, "must be in (0, "),
    _c("scan_target_short", "scan_target: [0.55, 0]\n", "scan_target", 1, "needs 3 coordinates"),
    _c("place_position_long", "pick:\n  place_position: [0.4, 0.3, 0]\n", "pick.place_position",
       2, "needs 2 coordinates"),
    _c("random_x_one", "object:\n  random_pose: {x: [0.5]}\n", "object.random_pose.x", 2,
       "needs 2 values [min, max] (m), got 1"),
    _c("random_y_reversed", "object:\n  random_pose: {y: [0.1, -0.1]}\n",
       "object.random_pose.y", 2, "needs [min, max] with min <= max, got [0.1, -0.1]"),
    _c("uniform_reversed", "object:\n  pose:\n    translation: !UniformVector {min: [0.6, 0, 0],"
                           " max: [0.5, 0, 0]}\n", "object.pose.translation", 3,
       "!UniformVector needs min <= max in every component; component 0: min 0.6 > max 0.5"),
    _c("uniform_rpy_reversed", "object:\n  pose:\n    rotation: !Rpy {deg: !UniformVector "
                               "{min: [0, 0, 90], max: [0, 0, -90]}}\n",
       "object.pose.rotation.deg", 3, "component 2: min 90 > max -90"),
    _c("uniform_short", "object:\n  pose:\n    translation: !UniformVector {min: [0.5, 0], "
                        "max: [0.6, 0]}\n", "object.pose.translation.min", 3, "needs 3 numbers"),
    _c("gaussian_zero_std", "object:\n  pose:\n    translation: !GaussianVector {mean: [0.55, 0, 0],"
                            " stddev: [0, 0, 0]}\n", "object.pose.translation.stddev", 3,
       "must be positive, got [0, 0, 0]"),
    _c("gaussian_scalar_negative", "object:\n  pose:\n    rotation: !AngleAxis {angle_deg: "
                                   "!Gaussian {mean: 0, stddev: -1}, axis: [0, 0, 1]}\n",
       "object.pose.rotation.angle_deg.stddev", 3, "must be positive, got -1"),
    _c("uniform_scalar_reversed", "object:\n  pose:\n    rotation: !AngleAxis {angle_deg: "
                                  "!Uniform {min: 10, max: -10}, axis: [0, 0, 1]}\n",
       "object.pose.rotation.angle_deg", 3, "!Uniform needs min <= max"),
    _c("axis_zero", "object:\n  pose:\n    rotation: !AngleAxis {angle_deg: 30, axis: [0, 0, 0]}\n",
       "object.pose.rotation.axis", 3, "must not be zero"),
    _c("settle_negative", "settle_time: -1\n", "settle_time", 1, "must be in [0, 60] s, got -1 s"),
    _c("max_time_huge", "max_time: 1e9\n", "max_time", 1, "must be in (0, 600] s"),
    _c("max_time_before_settle", "max_time: 0.1\n", "max_time", 1,
       "must exceed settle_time (0.5 s)"),
    _c("time_step_negative", "plant_config:\n  time_step: -0.001\n", "plant_config.time_step", 2,
       "must be in [1e-05, 0.01] s, got -0.001 s (gbh_drake needs a discrete plant"),
    _c("time_step_zero", "plant_config: {time_step: 0}\n", "plant_config.time_step", 1,
       "gbh_drake needs a discrete plant"),
    _c("time_step_tiny", "plant_config: {time_step: 1e-9}\n", "plant_config.time_step", 1,
       "smaller steps make a trial take hours"),
    _c("stiction_zero", "plant_config: {stiction_tolerance: 0}\n",
       "plant_config.stiction_tolerance", 1, "must be in (0, 1] m/s"),
    _c("near_rigid_negative", "plant_config: {sap_near_rigid_threshold: -1}\n",
       "plant_config.sap_near_rigid_threshold", 1, "must be in [0, 1000]"),
    _c("penetration_zero", "plant_config: {penetration_allowance: 0}\n",
       "plant_config.penetration_allowance", 1, "must be in (0, 1] m"),
    _c("publish_period_zero", "visualization:\n  publish_period: 0\n",
       "visualization.publish_period", 2, "must be in [0.001, 10] s"),
    _c("publish_period_tiny", "visualization:\n  publish_period: 1e-9\n",
       "visualization.publish_period", 2, "must be in [0.001, 10] s"),
    _c("num_views_zero", "scan:\n  num_views: 0\n", "scan.num_views", 2,
       "must be an integer in [1, 100], got 0"),
    _c("num_views_huge", "scan:\n  num_views: 100000\n", "scan.num_views", 2,
       "must be an integer in [1, 100]"),
    _c("image_huge", "scan:\n  width: 100000\n", "scan.width", 2,
       "must be an integer in [16, 4096], got 100000 (each view renders"),
    _c("image_zero", "scan:\n  height: 0\n", "scan.height", 2, "must be an integer in [16, 4096]"),
    _c("scan_pixels", "scan: {num_views: 100, width: 1920, height: 1080}\n", "scan.num_views", 1,
       "100 views of 1920 x 1080 pixels are 207 million pixels; at most 40 million"),
    _c("voxel_tiny", "scan:\n  voxel_size: 1e-6\n", "scan.voxel_size", 2,
       "smaller voxels take minutes and gigabytes"),
    _c("points_huge", "gbh:\n  n_points: 1000000000\n", "gbh.n_points", 2,
       "must be an integer in [100, 50000]"),
    _c("segment_work", "gbh: {max_contacts_per_cluster: 1000, n_segment_samples: 1000}\n",
       "gbh.n_segment_samples", 1, "= 1000000; at most 50000 per cluster"),
    _c("rays_huge", "gbh:\n  n_rays_per_plane: 100000\n", "gbh.n_rays_per_plane", 2,
       "must be an integer in [3, 720]"),
    _c("planner_huge", "pick:\n  planner_iterations: 1000000000\n", "pick.planner_iterations", 2,
       "must be an integer in [1, 100000]"),
    _c("contact_angle", "gbh:\n  contact_angle_deg: 120\n", "gbh.contact_angle_deg", 2,
       "must be in (0, 90) deg, got 120"),
    _c("monitor_period_tiny", "monitor: {period: 1e-9}\n", "monitor.period", 1,
       "must be in [0.001, 1] s"),
    _c("replay_fps_zero", "replay_fps: 0\n", "replay_fps", 1, "must be in (0, 120]"),
    _c("scale_zero", "object:\n  scale: 0\n", "object.scale", 2, "must be in (0, 1000]"),
    _c("density_negative", "object:\n  density: -5\n", "object.density", 2,
       "must be in [0, 25000] kg/m^3, got -5"),
    _c("mass_huge", "object:\n  mass: 5000\n", "object.mass", 2, "must be in [0, 100] kg"),
    _c("drop_negative", "object:\n  drop_height: -0.5\n", "object.drop_height", 2,
       "must be in [0, 0.5] m"),
    _c("yaw_range", "object:\n  random_pose: {yaw_deg: [-720, 0]}\n",
       "object.random_pose.yaw_deg[0]", 2, "must be in [-360, 360] deg"),
    _c("hand_force_over_max", "robot:\n  hand: {force: 200}\n", "robot.hand.force", 2,
       "must be <= robot.hand.max_force (140 N)"),
    _c("lift_reversed", "pick: {min_lift: 0.3, max_lift: 0.2}\n", "pick.min_lift", 1,
       "must be <= pick.max_lift (0.2 m)"),
    _c("approach_reversed", "pick: {approach_distance: 0.3, max_approach_distance: 0.2}\n",
       "pick.max_approach_distance", 1, "must be >= pick.approach_distance (0.3 m)"),
    _c("unloaded_fraction", "pick: {unloaded_fraction: 1.5}\n", "pick.unloaded_fraction", 1,
       "must be in (0, 1)"),
    _c("cage_force_over_max", "pick: {cage_test_force: 500}\n", "pick.cage_test_force", 1,
       "must be <= robot.hand.max_force (140 N)"),
    _c("distance_max_reversed", "scan: {distance: 0.8, distance_max: 0.6}\n",
       "scan.distance_max", 1, "must be >= scan.distance (0.8 m), got 0.6 m"),
    _c("depth_reversed", "scan: {depth_min: 2, depth_max: 1}\n", "scan.depth_min", 1,
       "must be < scan.distance (0.5 m), got 2 m: the camera would measure nothing there"),
    _c("depth_equal", "scan: {depth_min: 0.2, depth_max: 0.2, distance: 0.1, distance_max: 0.1, "
       "first_look_distance: 0.1}\n", "scan.distance", 1, "must exceed scan.depth_min (0.2 m)"),
    _c("elevation_straight_down", "scan: {elevation_deg: 90}\n", "scan.elevation_deg", 1,
       "must be in [0, 89] deg"),
    _c("first_look_scale", "scan: {first_look_scale: 64, width: 64, height: 64}\n",
       "scan.first_look_scale", 1, "leaves first-look images smaller than 8 pixels"),
    _c("p_c_over_points", "gbh: {n_points: 500, p_c: 600}\n", "gbh.p_c", 1,
       "must be <= gbh.n_points (500)"),
    _c("ground_normal_tilted", "gbh:\n  ground_normal: [0, 1, 0]\n", "gbh.ground_normal", 2,
       "the station's table is horizontal"),
    _c("ground_normal_zero", "gbh:\n  ground_normal: [0, 0, 0]\n", "gbh.ground_normal", 2,
       "the station's table is horizontal"),
    _c("ground_normal_short", "antipodal:\n  ground_normal: [0, 1]\n", "antipodal.ground_normal",
       2, "needs 3 components, got 2"),
    _c("antipodal_depths", "antipodal: {contact_depth: 0.01, min_contact_depth: 0.02}\n",
       "antipodal.min_contact_depth", 1, "must be <= antipodal.contact_depth (0.01 m)"),
    _c("sdf_trunc_small", "scan: {voxel_size: 0.004, sdf_trunc: 0.005}\n", "scan.sdf_trunc", 1,
       "must be >= 2 x scan.voxel_size (0.008 m), got 0.005 m"),
    # ---- silent acceptances: mass beyond the payload or under a gram, a lift never reached ----
    _c("named_mass_over_payload", "object:\n  name: kettle\n  mass: 50\n", "object.mass", 3,
       "makes kettle weigh 50 kg, above the Franka's payload (3 kg)"),
    _c("named_density_over_payload", "object: {name: kettle, density: 20000}\n", "object.density",
       1, "weigh 7.92 kg (density 20000 kg/m^3), above the Franka's payload"),
    _c("named_scale_over_payload", "object: {name: frying_pan, scale: 1.7}\n", "object.scale", 1,
       "above the Franka's payload (3 kg)"),
    _c("named_density_under_a_gram", "object:\n  density: 0.5\n", "object.density", 2,
       "makes mug_classic weigh 0.0666 g (density 0.5 kg/m^3), under 1 g"),
    _c("named_mass_under_a_gram", "object: {name: box, mass: 0.0005}\n", "object.mass", 1,
       "weigh 0.5 g, under 1 g"),
    _c("mesh_mass_over_payload", "object:\n  mesh: cube.obj\n  mass: 4\n", "object.mass", 3,
       "makes the mesh weigh 4 kg, above the Franka's payload", files={"cube.obj": CUBE_OBJ}),
    _c("lifted_above_max_lift", "monitor:\n  lifted_height: 1\n", "monitor.lifted_height", 2,
       "must be < pick.max_lift (0.4 m), got 1 m: the gripper rises at most that far"),
    _c("lifted_above_lowered_max_lift", "pick: {min_lift: 0.1, max_lift: 0.2}\n"
       "monitor: {lifted_height: 0.2}\n", "monitor.lifted_height", 2,
       "must be < pick.max_lift (0.2 m)"),
    # ---- bounds between fields, each once (the table: docs/errors.md, generated) ---------------
    _c("scoop_lift_above_max_lift", "grasp_method: gbh_scoop\nscoop: {min_lift: 0.3}\n"
       "pick: {max_lift: 0.25}\n", "scoop.min_lift", 2,
       "must be <= pick.max_lift (0.25 m), got 0.3 m: a scoop lifts at least scoop.min_lift"),
    _c("max_lift_below_the_scoops_default", "pick:\n  max_lift: 0.15\n", "pick.max_lift", 2,
       "must be >= scoop.min_lift (0.2 m), got 0.15 m: a scoop lifts at least"),
    _c("max_lift_lowered_by_an_override", "scoop: {min_lift: 0.3}\n", "pick.max_lift", 1,
       "must be >= scoop.min_lift (0.3 m), got 0.25 m", overrides=("pick: {max_lift: 0.25}",),
       origin=" (overrides)"),
    _c("cage_test_at_the_grasp_force", "robot: {hand: {force: 20}}\npick: {cage_test_force: 20}\n",
       "pick.cage_test_force", 2, "must be < robot.hand.force (20 N), got 20 N: the cage test "
       "relaxes the squeeze"),
    _c("cage_test_over_a_lowered_force", "pick: {cage_test_force: 10}\n", "robot.hand.force", 1,
       "must exceed pick.cage_test_force (10 N), got 5 N", overrides=("robot: {hand: {force: 5}}",),
       origin=" (overrides)"),
    _c("lifted_above_lift_clearance", "pick: {lift_clearance: 0.01}\n", "pick.lift_clearance", 1,
       "must be >= monitor.lifted_height (0.02 m), got 0.01 m: the pick lifts"),
    _c("lift_clearance_above_max_lift", "pick: {lift_clearance: 0.45}\n", "pick.lift_clearance",
       1, "must be < pick.max_lift (0.4 m), got 0.45 m: the object's lowest point rises no more"),
    _c("cluster_larger_than_the_samples", "gbh: {n_points: 500, min_cluster_size: 600}\n",
       "gbh.min_cluster_size", 1, "must be <= gbh.n_points (500), got 600: a cluster"),
    _c("clearance_beyond_the_hanging_distance", "gbh: {min_clearance: 0.05}\n",
       "gbh.min_clearance", 1, "must be < gbh.max_hanging_distance (0.05 m), got 0.05 m"),
    _c("hover_below_the_press", "scoop: {hover: 0.008, press_depth: 0.005}\n", "scoop.hover", 1,
       "must be < scoop.press_depth (0.005 m), got 0.008 m: the press"),
    _c("workspace_of_no_height", "scan: {crop_z_min: 0.3, crop_z_max: 0.3}\n", "scan.crop_z_max",
       1, "must exceed scan.crop_z_min (0.3 m), got 0.3 m: the workspace would be empty"),
    # ---- names among allowed values (ours and Drake's) ---------------------------------------
    _c("task_unknown", "task: dance\n", "task", 1, "must be one of pick, settle; got 'dance'"),
    _c("method_unknown", "grasp_method: graspnet\n", "grasp_method", 1,
       "must be one of gbh, antipodal, gbh_fallback"),
    _c("layout_unknown", "scan: {layout: grid}\n", "scan.layout", 1, "must be one of spiral, ring"),
    # ---- the grippers and the methods that need one (beyond the paper) -------------------------
    _c("gripper_unknown", "robot:\n  gripper: shiny\n", "robot.gripper", 2,
       "must be one of auto, paper, wedge; got 'shiny'"),
    _c("scoop_with_the_papers_bar", "grasp_method: gbh_scoop\nrobot: {gripper: paper}\n",
       "robot.gripper", 2, "paper: grasp_method gbh_scoop needs the wedge gripper"),
    _c("plus_with_the_papers_bar", "grasp_method: gbh_plus\nrobot:\n  gripper: paper\n",
       "robot.gripper", 3, "paper: grasp_method gbh_plus needs the wedge gripper"),
    _c("wedge_over_a_gripper_of_ones_own",
       "robot: {gripper: wedge}\n" + DIRECTIVES.replace(
           "package://gbh_drake/hook_gripper.sdf", "package://gbh_drake/hook_gripper_mine.sdf"),
       "robot.gripper", 1, "wedge: the directives add 'hook_gripper' from "
       "package://gbh_drake/hook_gripper_mine.sdf, not a packaged gripper"),
    _c("scoop_tilt", "scoop: {tilt_max_deg: 95}\n", "scoop.tilt_max_deg", 1,
       "must be in [0, 90] deg, got 95 deg"),
    _c("regrasps_too_many", "regrasp:\n  max_regrasps: 4\n", "regrasp.max_regrasps", 2,
       "must be an integer in [0, 3], got 4"),
    _c("regrasp_probability", "regrasp: {min_probability: 1.5}\n", "regrasp.min_probability", 1,
       "must be in [0, 1], got 1.5"),
    _c("orientation_unknown", "object:\n  mesh: cube.obj\n  orientation: upside_down\n",
       "object.orientation", 3, "must be one of keep, nearest_stable, most_probable",
       files={"cube.obj": CUBE_OBJ}),
    _c("contact_model_unknown", "plant_config:\n  contact_model: magic\n",
       "plant_config.contact_model", 2, "must be one of hydroelastic_with_fallback, point"),
    _c("contact_model_hydro_only", "plant_config:\n  contact_model: hydroelastic\n",
       "plant_config.contact_model", 2, "'hydroelastic' alone fails"),
    _c("approximation_tamsi", "plant_config:\n  discrete_contact_approximation: tamsi\n",
       "plant_config.discrete_contact_approximation", 2, "'tamsi' cannot"),
    _c("approximation_unknown", "plant_config:\n  discrete_contact_approximation: fast\n",
       "plant_config.discrete_contact_approximation", 2, "must be one of '', sap, similar, lagged"),
    _c("surface_unknown", "plant_config: {contact_surface_representation: quads}\n",
       "plant_config.contact_surface_representation", 1, "must be one of polygon, triangle"),
    _c("integrator_unknown", "simulator_config:\n  integration_scheme: rk45\n",
       "simulator_config.integration_scheme", 2, "must be one of bogacki_shampine3, cenic"),
    _c("accuracy_zero", "simulator_config: {accuracy: 0}\n", "simulator_config.accuracy", 1,
       "must be in (0, 1]"),
    _c("max_step_zero", "simulator_config: {max_step_size: 0}\n",
       "simulator_config.max_step_size", 1, "must be in (0, 10] s"),
    _c("realtime_negative", "simulator_config: {target_realtime_rate: -1}\n",
       "simulator_config.target_realtime_rate", 1, "must be in [0, 1000]"),
    # ---- what Drake refuses deep inside, checked at load -------------------------------------
    _c("camera_fps_zero", "cameras:\n- name: c\n  fps: 0\n", "cameras[0].fps", 3,
       "must be in (0, 240] frames/s, got 0"),
    _c("camera_output_delay", "cameras:\n- name: c\n  fps: 10\n  output_delay: 0.2\n",
       "cameras[0].output_delay", 4, "must be in [0, 0.1) s"),
    _c("camera_capture_offset", "cameras:\n- name: c\n  capture_offset: -1\n",
       "cameras[0].capture_offset", 3, "must be >= 0 s"),
    _c("camera_clipping", "cameras:\n- name: c\n  clipping_near: 2\n  clipping_far: 1\n",
       "cameras[0].clipping_near", 3, "needs 0 < clipping_near < clipping_far"),
    _c("camera_depth_range", "cameras:\n- name: c\n  z_near: 0.5\n  z_far: 600\n",
       "cameras[0].z_near", 3, "needs clipping_near <= z_near < z_far <= clipping_far"),
    _c("camera_center", "cameras:\n- name: c\n  center_x: -5\n", "cameras[0].center_x", 3,
       "must lie in (0, 640) pixels"),
    _c("camera_fov", "cameras:\n- name: c\n  focal: !FovDegrees {y: 0}\n", "cameras[0].focal.y", 3,
       "must be in (0, 180) deg"),
    _c("camera_focal", "cameras:\n- name: c\n  focal: !FocalLength {x: -1}\n",
       "cameras[0].focal.x", 3, "must be > 0 pixels, got -1 pixels"),
    _c("camera_size", "cameras:\n- name: c\n  width: 0\n", "cameras[0].width", 3,
       "must be an integer in [1, 4096], got 0"),
    _c("camera_no_name", "cameras:\n- name: ''\n", "cameras[0].name", 2, "must not be empty"),
    _c("camera_same_name", "cameras:\n- name: c\n- name: c\n", "cameras[1].name", 3,
       "'c' is used by two cameras"),
    _c("camera_gl", "cameras:\n- name: c\n  renderer_class: RenderEngineGl\n",
       "cameras[0].renderer_class", 3, "GL needs a display"),
    _c("camera_gltf", "cameras:\n- name: c\n  renderer_class: !RenderEngineGltfClientParams {}\n",
       "cameras[0].renderer_class", 3, "glTF-client a render server over the network"),
    _c("camera_glx", "cameras:\n- name: c\n  renderer_name: r2\n  renderer_class: "
       "!RenderEngineVtkParams {backend: GLX}\n", "cameras[0].renderer_class.backend", 4,
       "GLX needs an X display"),
    _c("camera_default_renderer_params", "cameras:\n- name: c\n  renderer_class: "
       "!RenderEngineVtkParams {default_clear_color: [1, 0, 0]}\n", "cameras[0].renderer_class",
       3, "the station's own VTK renderer"),
    _c("camera_renderer_unknown", "cameras:\n- name: c\n  renderer_class: Bogus\n",
       "cameras[0].renderer_class", 3, "must be '' or 'RenderEngineVtk'"),
    _c("camera_lcm_bus", "cameras:\n- name: c\n  lcm_bus: other\n", "cameras[0].lcm_bus", 3,
       "in-memory bus"),
    _c("camera_frame_unknown", "cameras:\n- name: c\n  X_PB: {base_frame: nope}\n",
       "cameras[0].X_PB.base_frame", 3, "no frame named 'nope'"),
    _c("camera_xbc_frame", "cameras:\n- name: c\n  X_BC: {base_frame: world}\n",
       "cameras[0].X_BC.base_frame", 3, "Drake uses base_frame only in X_PB"),
    _c("camera_random_pose", "cameras:\n- name: c\n  X_PB:\n    translation: !UniformVector "
                             "{min: [0, 0, 1], max: [0, 0, 2]}\n", "cameras[0].X_PB", 3,
       "must be a fixed pose"),
    _c("camera_too_many", "cameras:\n" + "".join(f"- name: c{i}\n" for i in range(9)), "cameras",
       1, "at most 8 cameras, got 9"),
    _c("scan_renderer_unknown", "scan: {renderer_name: vulkan}\n", "scan.renderer_name", 1,
       "no renderer named 'vulkan'"),
    _c("q_home_lower_limit", "robot:\n  q_home: [-3, -0.3, 0, -2.2, 0, 1.9, 0.78]\n",
       "robot.q_home[0]", 2, "outside panda_joint1's limits"),
    # ---- fields the run would not use: refused, not ignored ------------------------------------
    _c("pose_base_frame", "object:\n  pose:\n    base_frame: table\n", "object.pose.base_frame", 3,
       "base_frame 'table' is not supported"),
    _c("name_and_mesh", "object:\n  name: kettle\n  mesh: cube.obj\n", "object.mesh", 3,
       "give object.name or object.mesh, not both", files={"cube.obj": CUBE_OBJ}),
    _c("pose_and_random_pose", "object:\n  pose: {translation: [0.5, 0, 0]}\n  random_pose: {}\n",
       "object.random_pose", 3, "give object.pose or object.random_pose, not both"),
    _c("mass_and_density", "object: {mass: 1, density: 100}\n", "object.mass", 1,
       "give object.mass or object.density, not both"),
    _c("orientation_named", "object:\n  orientation: most_probable\n", "object.orientation", 2,
       "applies to mesh files"),
    _c("visual_lcm_bus", "visualization: {lcm_bus: lcm_udp}\n", "visualization.lcm_bus", 1,
       "must be 'default' (gbh_drake publishes on an in-memory bus only)"),
    _c("no_meshcat", "visualization: {enable_meshcat_creation: false}\n",
       "visualization.enable_meshcat_creation", 1, "a run always records its Meshcat replay"),
    _c("start_time", "simulator_config: {start_time: 2}\n", "simulator_config.start_time", 1,
       "the trial's phases count from t = 0"),
    _c("gbh_seed", "gbh:\n  seed: 4\n", "gbh.seed", 2, "unknown field"),
    _c("noise_seed", "scan:\n  noise_seed: 4\n", "scan.noise_seed", 2, "unknown field"),
    _c("antipodal_seed", "antipodal:\n  seed: 4\n", "antipodal.seed", 2, "unknown field"),
    _c("panda_joint_positions", "directives:\n- add_model: {name: panda, file: "
       "'package://gbh_drake/panda_arm.urdf', default_joint_positions: {panda_joint1: [0.5]}}\n"
       + WELD_ARM + GRIPPER + WELD_GRIPPER + TABLE + WELD_TABLE,
       "directives[0].add_model.default_joint_positions", 2, "robot.q_home"),
    # ---- the object ---------------------------------------------------------------------------
    _c("name_unknown", "object:\n  name: unicorn\n", "object.name", 2, "unknown object 'unicorn'"),
    _c("name_typo", "object:\n  name: mug_clasic\n", "object.name", 2,
       "did you mean 'mug_classic'?"),
    _c("name_empty", "object:\n  name: ''\n", "object", 1, "give a named object"),
    _c("named_too_small", "object:\n  scale: 1e-6\n", "object.scale", 2,
       "makes mug_classic 0.000132 mm across; objects of 1 cm to 2 m can be simulated"),
    _c("named_too_large", "object:\n  name: watering_can\n  scale: 20\n", "object.scale", 3,
       "objects of 1 cm to 2 m"),
    _c("mesh_missing", "object:\n  mesh: nope.obj\n", "object.mesh", 2, "file not found: "),
    _c("mesh_folder", "object:\n  mesh: .\n", "object.mesh", 2, "is a folder"),
    _c("mesh_not_a_mesh", "object:\n  mesh: broken.obj\n", "object.mesh", 2, "broken.obj",
       files={"broken.obj": "hello world\n"}),
    _c("mesh_flat", "object:\n  mesh: flat.obj\n", "object.mesh", 2, "flat.obj",
       files={"flat.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}),
    _c("mesh_nan", "object:\n  mesh: nan.obj\n", "object.mesh", 2, "nan.obj",
       files={"nan.obj": CUBE_OBJ.replace("v 0 0 0", "v nan 0 0")}),
    _c("mesh_empty_file", "object:\n  mesh: empty.stl\n", "object.mesh", 2, "empty.stl",
       files={"empty.stl": ""}),
    _c("mesh_unsupported", "object:\n  mesh: cube.dae\n", "object.mesh", 2, "cube.dae",
       files={"cube.dae": CUBE_OBJ}),
    _c("mesh_nul", "object:\n  mesh: \"a\\0b.obj\"\n", "object.mesh", 2, "NUL character"),
    # ---- directives ----------------------------------------------------------------------------
    _c("directives_empty", "directives: []\n", "directives", 1,
       "must add a model named 'panda'"),
    _c("directives_no_table", "directives:\n" + ARM + WELD_ARM + GRIPPER + WELD_GRIPPER,
       "directives", 1, "must add a model named 'table'"),
    _c("directives_relative", DIRECTIVES.replace("package://gbh_drake/table.sdf", "models/t.sdf"),
       "directives[4].add_model.file", 6, "is not a package:// or file:// URI"),
    _c("directives_http", DIRECTIVES.replace("package://gbh_drake/table.sdf",
                                             "https://example.com/t.sdf"),
       "directives[4].add_model.file", 6, "runs are offline"),
    _c("directives_remote_package", DIRECTIVES.replace("package://gbh_drake/table.sdf",
                                                       f"package://{REMOTE}/t.sdf"),
       "directives[4].add_model.file", 6, "downloaded by Drake on first use"),
    _c("directives_unknown_package", DIRECTIVES.replace("package://gbh_drake/table.sdf",
                                                        "package://furniture/t.sdf"),
       "directives[4].add_model.file", 6, "unknown package 'furniture'"),
    _c("directives_missing_file", DIRECTIVES.replace("table.sdf", "no_such_table.sdf"),
       "directives[4].add_model.file", 6, "file not found"),
    _c("directives_loop", DIRECTIVES + "- add_directives: {file: 'file://@DIR@/loop.dmd.yaml'}\n",
       "directives[6].add_directives.file", 8, "include each other in a loop",
       files={"loop.dmd.yaml": "directives:\n- add_directives: "
                               "{file: 'file://@DIR@/loop.dmd.yaml'}\n"}),
    _c("directives_nested_remote", DIRECTIVES + "- add_directives: {file: 'file://@DIR@/r.dmd.yaml'}\n",
       "directives[6].add_directives.file", 8, "downloaded by Drake on first use",
       files={"r.dmd.yaml": "directives:\n- add_model: {name: x, "
                            f"file: 'package://{REMOTE}/x.sdf'}}\n"}),
    _c("directives_bad_frame", DIRECTIVES.replace("table::table_top", "table::top"), "directives",
       1, "top"),
    _c("directives_model_clash", DIRECTIVES + "- add_model: {name: mug_classic, file: "
       "'package://gbh_drake/table.sdf'}\n", "directives", 1,
       "a model is named 'mug_classic' like the object"),
    # ---- the start state ------------------------------------------------------------------------
    _c("below_table", "object:\n  pose:\n    translation: [0.55, 0, -0.1]\n",
       "object.pose.translation", 3, "below the table top (z = 0)"),
    _c("below_table_uniform", "object:\n  pose:\n    translation: !UniformVector "
                              "{min: [0.5, 0, -0.2], max: [0.6, 0, 0]}\n",
       "object.pose.translation", 3, "below the table top"),
    _c("off_table", "object:\n  pose:\n    translation: [2, 0, 0]\n", "object.pose.translation", 3,
       "off the table top (x in [-0.35, 1.05], y in [-0.50, 0.50] m)"),
    _c("out_of_camera_reach", "object:\n  pose:\n    translation: [0.9, 0, 0]\n",
       "object.pose.translation", 3, "the cameras would not find it"),
    _c("random_out_of_camera_reach", "object:\n  random_pose: {x: [0.3, 0.9]}\n",
       "object.random_pose", 2, "the cameras would not find it"),
    _c("out_of_arm_reach", "scan_target: [1.0, 0.45, 0.06]\nobject:\n  pose:\n"
                           "    translation: [1.0, 0.45, 0]\n", "object.pose.translation", 4,
       "out of the Franka's reach"),
    _c("inside_robot", "scan_target: [0.1, 0, 0.06]\nobject:\n  pose:\n"
                       "    translation: [0.05, 0, 0]\n", "object.pose.translation", 4,
       "inside the robot's footprint"),
    _c("scan_target_off_table", "scan_target: [0.55, 3, 0.06]\n", "scan_target", 1,
       "scan_target at (0.55, 3) m is off the table top"),
    _c("scan_target_high", "scan_target: [0.55, 0, 3]\n", "scan_target", 1,
       "the scan looks for the object on the table"),
    _c("out_of_workspace", "scan:\n  crop_half_size_xy: 0.1\nobject:\n  pose:\n"
                           "    translation: [0.7, 0, 0]\n", "object.pose.translation", 5,
       "outside the scan's workspace"),
    _c("camera_beyond_depth", "scan:\n  distance: 2\n  distance_max: 2\n", "scan.distance", 2,
       "must be < scan.depth_max (1.5 m), got 2 m: the camera would measure nothing there"),
    _c("first_look_beyond_depth", "scan: {first_look_distance: 0.1}\n",
       "scan.first_look_distance", 1, "the camera would measure nothing there"),
    _c("place_off_table", "pick:\n  place_position: [0.4, 0.8]\n", "pick.place_position", 2,
       "the place position at (0.4, 0.8) m is off the table top"),
    _c("place_unreachable", "pick:\n  place_position: [0.95, 0.45]\n", "pick.place_position", 2,
       "out of the Franka's reach (about 0.85 m) by far"),
    # ---- output folder (field-level: the checks at run start are in test_outputs.py) ----------
    _c("output_dir_file", "output_dir: taken.txt\n", "output_dir", 1, "is a file, not a folder",
       files={"taken.txt": "x"}),
    _c("output_dir_nul", "output_dir: \"a\\0b\"\n", "output_dir", 1, "NUL character"),
    # ---- overrides (--set) ----------------------------------------------------------------------
    _c("override_unknown", "seed: 1\n", "sed", 1, "unknown field", overrides=("sed: 2",),
       origin=" (overrides)"),
    _c("override_type", "seed: 1\n", "seed", 1, "expected an integer, got 'x'",
       overrides=("seed: x",), origin=" (overrides)"),
    _c("override_range", "seed: 1\n", "scan.num_views", 2, "must be an integer in [1, 100]",
       overrides=("task: pick\nscan: {num_views: 0}",), origin=" (overrides)"),
    _c("override_duplicate", "seed: 1\n", "seed", 2, "given twice",
       overrides=("seed: 1\nseed: 2",), origin=" (overrides)"),
    _c("override_syntax", "seed: 1\n", "", 1, "not valid YAML", overrides=("seed: [",),
       origin=" (overrides)"),
    _c("override_second", "seed: 1\n", "task", 1, "must be one of pick, settle",
       overrides=("seed: 2", "task: fly"), origin=" (overrides 2 of 2)"),
    _c("override_points_at_file_line", "settle_time: 2\n", "max_time", 1,
       "must exceed settle_time", overrides=("max_time: 1",), origin=" (overrides)"),
    _c("override_root_list", "seed: 1\n", "", 1, "a scenario is a mapping",
       overrides=("[1, 2]",), origin=" (overrides)"),
]
