"""The camera scene renders what the plant's scene graph would, and is posed only when it renders."""

import numpy as np
import pytest
from pydrake.geometry import ColorRenderCamera, MakeRenderEngineVtk, RenderEngineVtkParams, Role
from pydrake.systems.analysis import Simulator
from station_helpers import make_station

from gbh_drake.perception.camera import make_depth_camera
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.viewpoints import camera_poses, look_at
from gbh_drake.station import RENDERER_NAME, scene_query_port
from gbh_drake.systems.camera_scene import CAMERA_SCENE_GRAPH


def _station_context(scenario):
    """A station whose arm is away from home (so the robot's poses matter), its context after
    a few steps, and the plant scene graph's context with Drake's VTK engine added to it."""
    station = make_station(scenario)
    context = station.CreateDefaultContext()
    plant = station.plant
    arm = plant.GetModelInstanceByName("panda")
    q = station.q_home + np.array([0.3, 0.2, -0.2, 0.3, 0.1, -0.2, 0.4])
    plant.SetPositions(plant.GetMyMutableContextFromRoot(context), arm, q)
    station.GetInputPort("panda.desired_state").FixValue(context, np.concatenate([q, np.zeros(7)]))
    station.GetInputPort("hook_gripper.command").FixValue(context, [0.04, 10.0, 0.0])
    Simulator(station, context).AdvanceTo(0.05)
    sg_context = station.scene_graph.GetMyMutableContextFromRoot(context)
    station.scene_graph.AddRenderer(sg_context, RENDERER_NAME,
                                    MakeRenderEngineVtk(RenderEngineVtkParams()))
    return station, context


@pytest.mark.sim
def test_the_camera_scene_renders_the_plant_scenes_pixels(scenario):
    station, context = _station_context(scenario)
    config = ScanConfig()
    camera = make_depth_camera(config)
    plant_query = station.GetOutputPort("query_object").Eval(context)
    camera_query = station.GetOutputPort("camera_query_object").Eval(context)
    world = plant_query.inspector().world_frame_id()
    # The scan's views of the object, and one that looks at the (moved) robot from its side.
    X_WCs = list(camera_poses(config, station.X_WO_initial.translation(), config.distance))
    X_WCs.append(look_at([1.2, 0.6, 0.9], [0.2, 0.0, 0.5]))  # the moved arm, from its side
    labels = ColorRenderCamera(camera.core(), False)
    for X_WC in X_WCs:
        np.testing.assert_array_equal(camera_query.RenderDepthImage(camera, world, X_WC).data,
                                      plant_query.RenderDepthImage(camera, world, X_WC).data)
        # The render labels (one per body) come with the perception properties.
        np.testing.assert_array_equal(camera_query.RenderLabelImage(labels, world, X_WC).data,
                                      plant_query.RenderLabelImage(labels, world, X_WC).data)
    # The last view sees the robot's links, the first the object: each body's pose is copied.
    robot = plant_query.RenderLabelImage(labels, world, X_WCs[-1]).data
    assert len(np.unique(robot)) >= 6


@pytest.mark.sim
def test_the_camera_scene_holds_the_perception_geometry_only(scenario):
    station = make_station(scenario)
    cameras = station.GetSubsystemByName(CAMERA_SCENE_GRAPH)
    plant_scene = station.scene_graph.model_inspector()
    camera_scene = cameras.model_inspector()
    assert camera_scene.NumGeometriesWithRole(Role.kPerception) == \
        plant_scene.NumGeometriesWithRole(Role.kPerception) > 0
    assert camera_scene.NumGeometriesWithRole(Role.kProximity) == 0
    assert cameras.HasRenderer(RENDERER_NAME)
    # The plant's scene graph renders nothing: no engine to re-pose at every step.
    assert station.scene_graph.RendererCount() == 0
    assert scene_query_port(RENDERER_NAME) == "camera_query_object"
    assert scene_query_port("overhead") == "query_object"


@pytest.mark.sim
def test_rendering_with_the_plants_query_object_names_the_port_to_use(scenario):
    from gbh_drake.perception.camera import render_depth_images

    station = make_station(scenario)
    context = station.CreateDefaultContext()
    query = station.GetOutputPort("query_object").Eval(context)
    with pytest.raises(ValueError, match="camera_query_object"):
        render_depth_images(query, make_depth_camera(ScanConfig()), [look_at([1, 0, 1], [0, 0, 0])])
