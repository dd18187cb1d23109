"""Fixtures for the object-set tests: every object built once per session; a distribution
installed in a folder of its own."""

import pytest
from mesh_shapes import CUBE_OBJ

from gbh_drake.objects import list_objects, make_object


@pytest.fixture(scope="session")
def specs():
    """name -> ObjectSpec for the whole set."""
    return {name: make_object(name) for name in list_objects()}


@pytest.fixture
def installed_toypkg(tmp_path, monkeypatch):
    """``toypkg`` 1.0 installed (as pip lays out a wheel) in a site folder on ``sys.path``:
    ``toypkg/assets/objects/mug/mug.obj`` and ``ring.obj``; returns the site folder."""
    site = tmp_path / "site"
    for inner in ("toypkg/assets/objects/mug/mug.obj", "toypkg/assets/objects/ring.obj"):
        (site / inner).parent.mkdir(parents=True, exist_ok=True)
        (site / inner).write_bytes(CUBE_OBJ)
    info = site / "toypkg-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: toypkg\nVersion: 1.0\n")
    (info / "RECORD").write_text("toypkg/assets/objects/mug/mug.obj,,\n"
                                 "toypkg/assets/objects/ring.obj,,\n")
    monkeypatch.syspath_prepend(str(site))
    return site
