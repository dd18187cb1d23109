"""Fixtures for the object-set tests: every object built once per session."""

import pytest

from gbh_drake.objects import list_objects, make_object


@pytest.fixture(scope="session")
def specs():
    """name -> ObjectSpec for the whole set."""
    return {name: make_object(name) for name in list_objects()}
