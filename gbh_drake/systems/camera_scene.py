"""The camera scene: a second ``SceneGraph`` that holds only what cameras see, posed on demand.

A ``SceneGraph`` updates the poses of every render engine it holds at every pose update, and a
``MultibodyPlant`` asks for a pose update at every time step (its contact queries need one). With
the scanner's VTK engine in the plant's scene graph, the robot's fourteen moving visuals were
re-posed in three VTK pipelines every 2 ms, about a sixth of the simulation's time, for images
taken a few times per trial (docs/speed.md).

:func:`add_camera_scene` copies the plant's perception geometry (shape, pose in its body's frame,
perception properties, hence the same render labels) into a second scene graph, named
``camera_scene_graph``, and adds the render engine there. :class:`CameraPoses` gives it each
body's pose from the plant's ``body_poses`` output. A scene graph updates its poses only when its
query object is evaluated, so the camera scene is posed when a camera renders, not at every step;
its images are the plant scene graph's images (same geometry, same poses: tested pixel for pixel).
"""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.geometry import (
    FramePoseVector,
    GeometryFrame,
    GeometryInstance,
    PerceptionProperties,
    RenderEngineVtkParams,
    Role,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import DiagramBuilder, LeafSystem

#: The camera scene graph's name in its diagram.
CAMERA_SCENE_GRAPH = "camera_scene_graph"


class CameraPoses(LeafSystem):
    """The poses of the camera scene's frames: each one's body pose from the plant.

    .. pydrake_system::

        name: CameraPoses
        input_ports:
        - body_poses
        output_ports:
        - geometry_pose

    ``body_poses``: the plant's output (X_WB of every body, by body index). ``geometry_pose``
    (``FramePoseVector``): X_WF of each frame this system registered, for the camera scene
    graph's source pose port.
    """

    def __init__(self, frames: dict):
        """``frames``: the camera scene's ``FrameId`` of each body index it poses."""
        super().__init__()
        self._frames = [(int(b), f) for b, f in frames.items()]
        self._poses = self.DeclareAbstractInputPort("body_poses",
                                                    AbstractValue.Make([RigidTransform()]))
        self.DeclareAbstractOutputPort(
            "geometry_pose", lambda: AbstractValue.Make(FramePoseVector()), self._calc,
            prerequisites_of_calc={self._poses.ticket()})

    def _calc(self, context, output) -> None:
        X_WBs = self._poses.Eval(context)
        poses = output.get_mutable_value()
        for body, frame in self._frames:
            poses.set_value(frame, X_WBs[body])


def add_camera_scene(builder: DiagramBuilder, plant: MultibodyPlant, scene_graph: SceneGraph,
                     renderer_name: str, params: RenderEngineVtkParams | None = None
                     ) -> SceneGraph:
    """Adds the camera scene of ``plant`` (finalized, registered with ``scene_graph``) to
    ``builder``: its perception geometry in a second scene graph with a VTK engine named
    ``renderer_name`` (``params``: its parameters, default Drake's), posed from the plant's
    ``body_poses``. Returns that scene graph: render with its query output port."""
    from pydrake.geometry import MakeRenderEngineVtk

    cameras = builder.AddNamedSystem(CAMERA_SCENE_GRAPH, SceneGraph())
    cameras.AddRenderer(renderer_name, MakeRenderEngineVtk(params or RenderEngineVtkParams()))
    source = cameras.RegisterSource("camera_scene")
    inspector = scene_graph.model_inspector()
    world = inspector.world_frame_id()
    frames = {}
    for g in inspector.GetAllGeometryIds(Role.kPerception):
        instance = GeometryInstance(inspector.GetPoseInFrame(g), inspector.GetShape(g),
                                    inspector.GetName(g))
        frame = inspector.GetFrameId(g)
        if frame == world:
            copy = cameras.RegisterAnchoredGeometry(source, instance)
        else:
            body = plant.GetBodyFromFrameId(frame).index()
            if body not in frames:
                frames[body] = cameras.RegisterFrame(
                    source, GeometryFrame(inspector.GetName(frame),
                                          inspector.GetFrameGroup(frame)))
            copy = cameras.RegisterGeometry(source, frames[body], instance)
        cameras.AssignRole(source, copy, PerceptionProperties(inspector.GetPerceptionProperties(g)))
    poses = builder.AddNamedSystem("camera_poses", CameraPoses(frames))
    builder.Connect(plant.get_body_poses_output_port(), poses.GetInputPort("body_poses"))
    builder.Connect(poses.GetOutputPort("geometry_pose"), cameras.get_source_pose_port(source))
    return cameras
