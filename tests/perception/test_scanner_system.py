"""The Scanner LeafSystem: ports, caching (scan once, or rescan when the scene moves)."""

from pydrake.math import RigidTransform

from gbh_drake.perception.scan import ScanResult


def test_scanner_outputs_the_mesh_once(mug_scene):
    context = mug_scene.diagram.CreateDefaultContext()
    scanner = mug_scene.scanner
    assert scanner.get_input_port().get_name() == "query_object"
    port = scanner.GetOutputPort("mesh_W")
    result = port.Eval(scanner.GetMyContextFromRoot(context))
    assert isinstance(result, ScanResult) and not result.empty and len(result.X_WCs) == 10
    _move_mug(mug_scene, context)
    assert port.Eval(scanner.GetMyContextFromRoot(context)) is result  # cached: not rescanned


def test_rescanner_follows_the_scene(mug_scene):
    context = mug_scene.diagram.CreateDefaultContext()
    port = mug_scene.rescanner.GetOutputPort("mesh_W")
    scanner_context = mug_scene.rescanner.GetMyContextFromRoot(context)
    before = port.Eval(scanner_context)
    assert port.Eval(scanner_context) is before  # nothing moved: cached
    _move_mug(mug_scene, context)
    after = port.Eval(scanner_context)
    assert after.empty  # the mug left the crop box
    assert not before.empty


def _move_mug(mug_scene, context) -> None:
    plant = mug_scene.station.plant
    plant.SetFreeBodyPose(plant.GetMyMutableContextFromRoot(context),
                          mug_scene.station.object_body(), RigidTransform([0.55, 0.5, 0.0]))
