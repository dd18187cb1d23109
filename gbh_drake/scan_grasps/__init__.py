"""Grasps for a scan you have: a mesh, a point cloud or depth images of an object on a table,
in, ranked hook grasps in the robot's base frame B out (``gbh grasps``, ``gbh_drake.grasps``).

* :mod:`~gbh_drake.scan_grasps.views`: the folder of depth images and its ``views.yaml``;
* :mod:`~gbh_drake.scan_grasps.inputs`: reading any input into a scan in B
  (:mod:`~gbh_drake.scan_grasps.depth_input` for depth images, through the simulated scan's own
  functions; :mod:`~gbh_drake.scan_grasps.cloud` for point clouds);
* :mod:`~gbh_drake.scan_grasps.api`: :func:`grasps`, the GbH core on it;
* :mod:`~gbh_drake.scan_grasps.waypoints`: pre-grasp, grasp, closed and lift poses;
* :mod:`~gbh_drake.scan_grasps.result` and :mod:`~gbh_drake.scan_grasps.document`: the result
  and its versioned JSON/YAML document (``docs/grasps_schema.md``);
* :mod:`~gbh_drake.scan_grasps.page`: a static Meshcat page of it;
* :mod:`~gbh_drake.scan_grasps.run_export`: what ``gbh run`` writes of its scan.

(Not named ``grasps``: ``gbh_drake.grasps`` is the function.)
"""
