"""What is imported when: Open3D with its machine-learning and visualisation subpackages
deferred (the pipeline's parts work, scikit-learn and Dash are not imported, the deferred
subpackages still work when asked for), and trimesh and scipy only once used, not by
``import gbh_drake.systems`` (in a fresh interpreter each, as an import happens once)."""

import subprocess
import sys
import textwrap


def run(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                         text=True, check=False, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


def test_deferred_subpackages_are_not_imported_until_used():
    out = run("""
        import sys
        from gbh_drake.core.o3d import open3d
        o3d = open3d()
        assert o3d.pipelines.integration.ScalableTSDFVolume is not None
        assert o3d.t.geometry.RaycastingScene is not None
        print("sklearn" in sys.modules, "dash" in sys.modules)
        print(o3d.ml.datasets.SemanticKITTI.__name__, "sklearn" in sys.modules)
        import open3d.ml.datasets as datasets
        import open3d.visualization.rendering as rendering
        assert datasets is sys.modules["open3d.ml.datasets"] and rendering is not None
        print(o3d.visualization.rendering.OffscreenRenderer.__name__,
              o3d.ml is sys.modules["open3d.ml"])
        print(open3d() is o3d)
    """)
    assert out.splitlines() == ["False False", "SemanticKITTI True",
                                "OffscreenRenderer True", "True"]


def test_open3d_imported_before_is_returned_as_it_is():
    out = run("""
        import sys
        import open3d
        from gbh_drake.core.o3d import open3d as deferred
        print(deferred() is open3d, type(open3d.ml).__name__, "sklearn" in sys.modules)
    """)
    assert out == "True module True"


def test_the_systems_import_without_trimesh_or_scipy_and_use_them_when_needed():
    out = run("""
        import sys
        import gbh_drake.systems
        from gbh_drake.core import hangability
        print("trimesh" in sys.modules, "scipy" in sys.modules, "open3d" in sys.modules)
        import numpy as np
        labels = hangability.cluster_points(np.array([[0, 0, 0], [0, 0, 0.001], [1, 0, 0]]),
                                            radius=0.01, min_size=2)
        print(labels.tolist(), "scipy.spatial" in sys.modules)
        import trimesh
        print(isinstance(trimesh.creation.box(), hangability.trimesh.Trimesh))
    """)
    assert out.splitlines() == ["False False False", "[0, 0, -1] True", "True"]
