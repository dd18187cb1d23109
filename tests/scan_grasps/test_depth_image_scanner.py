"""The DepthImageScanner on camera streams: Drake's RgbdSensors render the depth images a
Scanner renders itself, at the same poses; the scan is the Scanner's, and GbH's systems rank the
same grasps on it."""

import numpy as np
import pytest
from network_sockets import network_exposure
from pydrake.math import RigidTransform
from pydrake.systems.sensors import RgbdSensor

from gbh_drake.core.params import GbhParams
from gbh_drake.perception.camera import CameraIntrinsics, make_depth_camera
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scenes import build_scene
from gbh_drake.perception.viewpoints import camera_poses
from gbh_drake.systems import (
    DepthImageScanner,
    GraspScorer,
    GraspSynthesizer,
    HangabilityDetector,
    Scanner,
)

pytestmark = pytest.mark.sim

#: Three views from fixed poses round the mug (nothing aimed: a camera does not move itself).
CONFIG = ScanConfig(num_views=3, aim_views=False, width=320, height=240)
P_WT = np.array([0.55, 0.0, 0.05])


@pytest.fixture(scope="module")
def cameras(tmp_path_factory):
    """The mug scene with three RgbdSensors feeding a DepthImageScanner, a Scanner looking from
    the same poses, and GbH's three stages behind each."""
    made = {}

    def add(builder, scene_graph):
        camera = make_depth_camera(CONFIG)
        poses = camera_poses(CONFIG, P_WT)
        scanner = builder.AddNamedSystem("depth_image_scanner", DepthImageScanner(
            CONFIG, CameraIntrinsics.from_config(CONFIG), P_WT, num_cameras=len(poses)))
        for i, X_WC in enumerate(poses):
            sensor = builder.AddNamedSystem(f"camera_{i}", RgbdSensor(
                scene_graph.world_frame_id(), X_WC, camera))
            builder.Connect(scene_graph.get_query_output_port(), sensor.query_object_input_port())
            builder.Connect(sensor.depth_image_32F_output_port(),
                            scanner.GetInputPort(f"depth_image_{i}"))
            builder.Connect(sensor.body_pose_in_world_output_port(),
                            scanner.GetInputPort(f"X_WC_{i}"))
        reference = builder.AddNamedSystem("scanner", Scanner(CONFIG, P_WT))
        builder.Connect(scene_graph.get_query_output_port(), reference.get_input_port())
        for name, source in (("streams", scanner), ("rendered", reference)):
            detector = builder.AddNamedSystem(f"{name}_detector", HangabilityDetector(
                GbhParams(), seed=3))
            synthesizer = builder.AddNamedSystem(f"{name}_synthesizer", GraspSynthesizer())
            scorer = builder.AddNamedSystem(f"{name}_scorer", GraspScorer())
            builder.Connect(source.GetOutputPort("mesh_W"), detector.get_input_port())
            builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
            builder.Connect(synthesizer.get_output_port(), scorer.get_input_port())
            made[name] = (source, scorer)

    scene = build_scene("mug_classic", tmp_path_factory.mktemp("mug"), yaw_deg=30.0,
                        systems=[add])
    return scene, made


def _eval(scene, system, port):
    return system.GetOutputPort(port).Eval(system.GetMyContextFromRoot(scene.context))


def test_the_scan_of_camera_streams_is_the_scanners(cameras):
    scene, made = cameras
    streams = _eval(scene, made["streams"][0], "mesh_W")
    rendered = _eval(scene, made["rendered"][0], "mesh_W")
    assert not streams.empty and not rendered.empty, (streams.message, rendered.message)
    np.testing.assert_array_equal(streams.mesh_W.faces, rendered.mesh_W.faces)
    np.testing.assert_array_equal(streams.mesh_W.vertices, rendered.mesh_W.vertices)
    np.testing.assert_array_equal(streams.p_WQ, rendered.p_WQ)
    np.testing.assert_array_equal(streams.table.normal_W, rendered.table.normal_W)
    assert (streams.table.height, streams.table.source) == (rendered.table.height,
                                                            rendered.table.source)
    assert streams.warnings == rendered.warnings
    for a, b in zip(streams.free_space.views, rendered.free_space.views, strict=True):
        np.testing.assert_array_equal(a.depth, b.depth)
        np.testing.assert_allclose(a.X_CW, b.X_CW, atol=1e-12)


def test_the_gbh_systems_rank_the_same_grasps_on_the_streams(cameras):
    scene, made = cameras
    streams = _eval(scene, made["streams"][1], "ranked_grasps")
    rendered = _eval(scene, made["rendered"][1], "ranked_grasps")
    assert streams, "no grasp on the mug's handle"
    assert [g.kind for g in streams] == [g.kind for g in rendered]
    for a, b in zip(streams, rendered, strict=True):
        np.testing.assert_allclose(a.X_WG, b.X_WG, atol=1e-9)


def test_a_wrong_image_size_names_the_port():
    scanner = DepthImageScanner(CONFIG, CameraIntrinsics.from_config(CONFIG), P_WT)
    context = scanner.CreateDefaultContext()
    from pydrake.systems.sensors import ImageDepth32F

    scanner.GetInputPort("depth_image_0").FixValue(context, ImageDepth32F(64, 48))
    scanner.GetInputPort("X_WC_0").FixValue(context, RigidTransform())
    with pytest.raises(ValueError, match="depth_image_0 is 64x48 pixels; the intrinsics say 320x240"):
        scanner.GetOutputPort("mesh_W").Eval(context)


def test_capture_times_take_every_camera_each_time_and_fuse_after_the_last():
    """Two cameras (two of the sample views' images and poses on constant sources), captured at
    0.1 s and 0.2 s: the placeholder until then, a scan of the four views after."""
    from pydrake.common.value import AbstractValue
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import ConstantValueSource
    from pydrake.systems.sensors import ImageDepth32F

    from gbh_drake import REPO_ROOT
    from gbh_drake.scan_grasps.views import read_views
    from gbh_drake.systems.scanner import scan_pending

    views = read_views(REPO_ROOT / "tests" / "scan_grasps" / "data" / "mug_views").views
    builder = DiagramBuilder()
    scanner = builder.AddSystem(DepthImageScanner(
        ScanConfig(), views.intrinsics, [0.55, 0.0, 0.06], num_cameras=2,
        capture_times=[0.1, 0.2], sensor_error=views.depth_error))
    for i in range(2):
        image = ImageDepth32F(views.intrinsics.width, views.intrinsics.height)
        image.mutable_data[:, :, 0] = views.depths[i]
        for port, value in ((f"depth_image_{i}", image), (f"X_WC_{i}",
                                                          RigidTransform(views.X_BCs[i]))):
            source = builder.AddSystem(ConstantValueSource(AbstractValue.Make(value)))
            builder.Connect(source.get_output_port(), scanner.GetInputPort(port))
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = scanner.GetMyContextFromRoot(simulator.get_mutable_context())
    simulator.AdvanceTo(0.15)
    assert scan_pending(scanner.GetOutputPort("mesh_W").Eval(context))
    simulator.AdvanceTo(0.25)
    scan = scanner.GetOutputPort("mesh_W").Eval(context)
    assert not scan_pending(scan) and not scan.empty, scan.message
    assert len(scan.X_WCs) == 4 and scan.taken_at == pytest.approx(0.2)
    np.testing.assert_allclose(scan.X_WCs[2].GetAsMatrix4(), views.X_BCs[0], atol=1e-12)


def test_the_pages_example_of_cameras_of_ones_own_runs(capsys):
    """docs/grasps.md's DepthImageScanner example, as written: a plant, scene graph and cameras
    (CameraConfig) of one's own, scanned and ranked."""
    import re

    from gbh_drake import REPO_ROOT

    page = (REPO_ROOT / "docs" / "grasps.md").read_text()
    after = page[page.index("<!-- depth-image-scanner -->"):]
    code = re.search(r"```python\n(.*?)```", after, re.S).group(1)
    before = set(network_exposure())
    exec(compile(code, "docs/grasps.md", "exec"), {})
    assert capsys.readouterr().out == "True parallel (4, 4)\n"
    # Its cameras publish on an in-memory bus: no UDP socket (Drake's default LCM) is left open.
    assert set(network_exposure()) - before == set()
