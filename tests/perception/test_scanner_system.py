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
