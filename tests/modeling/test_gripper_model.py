"""The hook gripper that collides in simulation is the one the algorithm reasons about."""

import numpy as np
import pytest
from pydrake.geometry import Box as DrakeBox
from pydrake.geometry import Role
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.systems.framework import DiagramBuilder

from gbh_drake import MODELS_DIR, REPO_ROOT
from gbh_drake.core.gripper import HOOK_GRIPPER, WEDGE_GRIPPER, HookGripperGeometry
from gbh_drake.modeling.gripper_sdf import (
    BAR_DEPLOYED,
    BAR_RETRACTED,
    GRIPPER_SDF,
    WEDGE_BAR_OBJ,
    WEDGE_GRIPPER_SDF,
    make_gripper_sdf,
    wedge_bar_obj,
)
from gbh_drake.modeling.package_map import make_parser


def test_sdf_on_disk_is_generated_from_the_geometry_module():
    assert GRIPPER_SDF.read_text() == make_gripper_sdf(), (
        "models/hook_gripper.sdf is stale: run python -m gbh_drake.modeling.gripper_sdf"
    )


def test_wedge_variant_on_disk_is_generated_from_the_geometry_module():
    assert WEDGE_GRIPPER_SDF.read_text() == make_gripper_sdf(WEDGE_GRIPPER)
    assert WEDGE_BAR_OBJ.read_text() == wedge_bar_obj()


def test_wedge_nose_is_bounded_by_the_rod_width():
    with pytest.raises(ValueError, match="bar_nose"):
        HookGripperGeometry(bar_nose=0.009)
    with pytest.raises(ValueError, match="bar_ramp"):
        HookGripperGeometry(bar_ramp=0.023)  # the inner face would end within a rod of the L rod
    assert HOOK_GRIPPER.bar_nose == WEDGE_GRIPPER.bar_nose == 0.0
    assert HOOK_GRIPPER.ramp == 0.0 and WEDGE_GRIPPER.ramp == 0.016
    # The default wedge's solid model is the paper's: its chamfer lies inside the bar's box.
    for g in (HOOK_GRIPPER, WEDGE_GRIPPER):
        assert {b.name for b in g.solid_boxes_G()} == {"hand", "straight_rod", "l_rod", "bar"}
    assert WEDGE_GRIPPER.solid_boxes_G() == HOOK_GRIPPER.solid_boxes_G()
    assert "bar_nose" in {b.name for b in HookGripperGeometry(bar_nose=0.008).solid_boxes_G()}


def test_arm_urdf_is_current():
    import importlib.util

    spec = importlib.util.spec_from_file_location("m", REPO_ROOT / "tools" / "make_panda_urdf.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert (MODELS_DIR / "panda_arm.urdf").read_text() == module.make_urdf()


def _gripper_plant(sdf=GRIPPER_SDF):
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, 0.001)
    (gripper,) = make_parser(plant).AddModels(str(sdf))
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("panda_hand"))
    plant.Finalize()
    diagram = builder.Build()
    return diagram, plant, scene_graph, gripper


@pytest.mark.parametrize(("q", "retracted"), [
    (HOOK_GRIPPER.q_closed, False), (0.03, False), (HOOK_GRIPPER.q_open, False),
    (HOOK_GRIPPER.q_closed_retracted, True), (0.03, True)])
def test_collision_boxes_match_solid_model(q, retracted):
    diagram, plant, scene_graph, gripper = _gripper_plant()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyContextFromRoot(context)
    bar = BAR_RETRACTED if retracted else BAR_DEPLOYED
    plant.SetPositions(plant_context, gripper, [q, q, bar])
    inspector = scene_graph.model_inspector()
    G = plant.GetFrameByName("G")
    found = {}
    for body_index in plant.GetBodyIndices(gripper):
        body = plant.get_body(body_index)
        X_GB = plant.CalcRelativeTransform(plant_context, G, body.body_frame())
        for gid in plant.GetCollisionGeometriesForBody(body):
            shape = inspector.GetShape(gid)
            assert isinstance(shape, DrakeBox)
            X_GGeom = X_GB @ inspector.GetPoseInFrame(gid)
            # Boxes are axis-aligned in G (the folded bar is turned a quarter about x_G).
            R = np.abs(X_GGeom.rotation().matrix())
            size = R @ np.array([shape.width(), shape.depth(), shape.height()])
            np.testing.assert_allclose(R, np.round(R), atol=1e-9)
            found[inspector.GetName(gid).split("::")[-1]] = (X_GGeom.translation(), size)
    expected = {b.name: b for b in HOOK_GRIPPER.solid_boxes_G(q, bar_retracted=retracted)}
    assert set(found) == set(expected)
    for name, box in expected.items():
        np.testing.assert_allclose(found[name][0], box.center, atol=1e-9, err_msg=name)
        np.testing.assert_allclose(found[name][1], box.size, atol=1e-9, err_msg=name)
    # Every geometry has hydroelastic properties (compliant): real hydroelastic contact.
    for gid in inspector.GetAllGeometryIds(Role.kProximity):
        props = inspector.GetProximityProperties(gid)
        assert props.HasProperty("hydroelastic", "compliance_type")
        assert props.GetProperty("hydroelastic", "hydroelastic_modulus") > 0


def test_keypoints_lie_on_the_model():
    """p2 is the straight rod's tip, p1 the bar's tip, p3 the bend, all on the model's centre lines."""
    diagram, plant, _, gripper = _gripper_plant()
    plant_context = plant.GetMyContextFromRoot(diagram.CreateDefaultContext())
    q = 0.03
    plant.SetPositions(plant_context, gripper, [q, q, BAR_DEPLOYED])
    G = plant.GetFrameByName("G")
    p = HOOK_GRIPPER.keypoints_G(q)
    straight = plant.GetBodyByName("straight_finger").body_frame()
    l_rod = plant.GetBodyByName("l_finger").body_frame()
    lf = HOOK_GRIPPER.finger_length
    np.testing.assert_allclose(
        plant.CalcRelativeTransform(plant_context, G, straight).translation() + [0, 0, lf], p["p2"]
    )
    np.testing.assert_allclose(
        plant.CalcRelativeTransform(plant_context, G, l_rod).translation() + [0, 0, lf], p["p3"]
    )
    bar = {b.name: b for b in HOOK_GRIPPER.solid_boxes_G(q)}["bar"]
    assert bar.center[1] + bar.half_extents[1] == pytest.approx(p["p1"][1])
    np.testing.assert_allclose(HOOK_GRIPPER.n1_G, [0, 0, -1])
    np.testing.assert_allclose(HOOK_GRIPPER.n2_G, [0, 1, 0])
    # The fingers' joints range from the rods touching (the bar folded; with the bar out its
    # tip stops them at q_closed) to fully open; the bar's from folded to deployed.
    for name in ("straight_finger_joint", "l_finger_joint"):
        joint = plant.GetJointByName(name)
        assert joint.position_lower_limits()[0] == pytest.approx(HOOK_GRIPPER.q_closed_retracted)
        assert joint.position_upper_limits()[0] == pytest.approx(HOOK_GRIPPER.q_open)
    bar = plant.GetJointByName("bar_joint")
    assert bar.position_lower_limits()[0] == pytest.approx(HOOK_GRIPPER.bar_retracted_angle)
    assert bar.position_upper_limits()[0] == pytest.approx(BAR_DEPLOYED)


def test_closed_gripper_closes_the_loop():
    """At q_closed the bar's tip touches the straight rod's inner face (no gap to slip through)."""
    boxes = {b.name: b for b in HOOK_GRIPPER.solid_boxes_G(HOOK_GRIPPER.q_closed)}
    bar_tip = boxes["bar"].center[1] + boxes["bar"].half_extents[1]
    rod_face = boxes["straight_rod"].center[1] - boxes["straight_rod"].half_extents[1]
    assert bar_tip == pytest.approx(rod_face)


@pytest.mark.parametrize("q", [WEDGE_GRIPPER.q_open, WEDGE_GRIPPER.q_closed])
def test_wedge_bar_in_the_model_is_the_geometry_modules(q):
    """The wedge model's bar is a compliant convex mesh whose points lie in the solid model's
    bar box and fill its extent; the rest of the model is the paper's."""
    import trimesh
    from pydrake.geometry import Mesh

    diagram, plant, scene_graph, gripper = _gripper_plant(WEDGE_GRIPPER_SDF)
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyContextFromRoot(context)
    plant.SetPositions(plant_context, gripper, [q, q, BAR_DEPLOYED])
    inspector = scene_graph.model_inspector()
    G = plant.GetFrameByName("G")
    bar = plant.GetBodyByName("bar")
    (gid,) = plant.GetCollisionGeometriesForBody(bar)
    assert isinstance(inspector.GetShape(gid), Mesh)
    props = inspector.GetProximityProperties(gid)
    assert props.HasProperty("hydroelastic", "compliance_type")
    assert props.GetProperty("hydroelastic", "hydroelastic_modulus") > 0
    X_GGeom = plant.CalcRelativeTransform(plant_context, G, bar.body_frame()) @ \
        inspector.GetPoseInFrame(gid)
    mesh = trimesh.load(str(WEDGE_BAR_OBJ), process=False)
    p_G = trimesh.transform_points(mesh.vertices, X_GGeom.GetAsMatrix4())
    boxes = [b for b in WEDGE_GRIPPER.solid_boxes_G(q) if b.name in ("bar", "bar_nose")]
    lo = np.min([np.subtract(b.center, b.half_extents) for b in boxes], axis=0)
    hi = np.max([np.add(b.center, b.half_extents) for b in boxes], axis=0)
    np.testing.assert_allclose(p_G.min(axis=0), lo, atol=1e-9)
    np.testing.assert_allclose(p_G.max(axis=0), hi, atol=1e-9)
    # The wedge's sharp edge is the bar's outer face (farthest from the palm), at the tip p1;
    # its inner face (toward the palm) ends a ramp's length short of it.
    far = p_G[:, 1] > p_G[:, 1].max() - 1e-9
    assert np.all(p_G[far, 2] == pytest.approx(WEDGE_GRIPPER.finger_length
                                               + 0.5 * WEDGE_GRIPPER.rod_width))
    p1 = WEDGE_GRIPPER.keypoints_G(q)["p1"]
    assert p_G[far, 1][0] == pytest.approx(p1[1])
    inner = p_G[:, 2] < WEDGE_GRIPPER.finger_length
    assert p_G[inner, 1].max() == pytest.approx(p1[1] - WEDGE_GRIPPER.ramp)
    # Closed, the edge meets the straight rod's inner face: the loop is closed.
    if q == WEDGE_GRIPPER.q_closed:
        rod = {b.name: b for b in WEDGE_GRIPPER.solid_boxes_G(q)}["straight_rod"]
        assert p1[1] == pytest.approx(rod.center[1] - rod.half_extents[1])
