"""The Scanner LeafSystem on a scene graph: its ports, and a cached scan of the object."""

import numpy as np
import pytest

from gbh_drake.perception.scan import ScanResult


@pytest.mark.sim
def test_scanner_outputs_the_scan(mug_scene):
    context = mug_scene.diagram.CreateDefaultContext()
    scanner = mug_scene.scanner
    assert scanner.get_input_port().get_name() == "query_object"
    port = scanner.GetOutputPort("mesh_W")
    result = port.Eval(scanner.GetMyContextFromRoot(context))
    assert isinstance(result, ScanResult) and not result.empty and len(result.X_WCs) == 10
    assert result.warnings == []
    np.testing.assert_allclose(result.mesh_W.bounds, mug_scene.mesh_W.bounds, atol=0.004)
    assert port.Eval(scanner.GetMyContextFromRoot(context)) is result  # cached


def test_empty_result_says_why():
    result = ScanResult.empty_result("not scanned yet")
    assert result.empty and result.message == "not scanned yet"
    assert len(result.mesh_W.faces) == 0 and result.p_WQ.shape == (0, 3)
    assert result.warnings == []


@pytest.mark.parametrize(("args", "kwargs", "message"), [
    ((None, [0.55, 0.0, 0.06]), {}, "Scanner(): config: expected a ScanConfig (a scenario's "
                                    "scan), got None (a NoneType)"),
    (("config", 0.5), {}, "Scanner(): p_WT: expected 3 finite coordinates (x, y, z in m; a "
                          "scenario's scan_target), got 0.5 (a float)"),
    (("config", [0.55, 0.0]), {}, "Scanner(): p_WT: expected 3 finite coordinates (x, y, z in m; "
                                  "a scenario's scan_target), got [0.55, 0.0] (a list)"),
    (("config", [0.55, 0.0, 0.06]), {"scan_time": "1"},
     "Scanner(): scan_time: expected a time >= 0 (s) or None, got '1' (a str)"),
])
def test_the_scanner_names_an_argument_of_the_wrong_type(args, kwargs, message):
    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.systems import Scanner

    args = tuple(ScanConfig() if a == "config" else a for a in args)
    with pytest.raises(TypeError) as info:
        Scanner(*args, **kwargs)
    assert str(info.value) == message


def test_a_scene_graph_of_ones_own_without_the_renderer_says_how_to_add_it():
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
    from pydrake.systems.framework import DiagramBuilder

    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.systems import Scanner

    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=0.001)
    plant.Finalize()
    scanner = builder.AddSystem(Scanner(ScanConfig(renderer_name="vtk"), [0.55, 0.0, 0.06]))
    builder.Connect(scene_graph.get_query_output_port(), scanner.get_input_port())
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    with pytest.raises(ValueError, match=r"ScanConfig.renderer_name \('vtk'\): add a render "
                                         r"engine of that name .*AddRenderer\('vtk', "):
        scanner.GetOutputPort("mesh_W").Eval(scanner.GetMyContextFromRoot(context))
