"""ScanConfig loads with Drake's yaml_load_typed and rejects bad values by field name."""

import pytest
from pydrake.common.yaml import yaml_load_typed

from gbh_drake.perception.config import ScanConfig


def test_loads_from_yaml_with_defaults():
    config = yaml_load_typed(schema=ScanConfig, data="num_views: 1\nnoise: true\nvoxel_size: 0.003")
    assert (config.num_views, config.noise, config.voxel_size) == (1, True, 0.003)
    assert config.distance == ScanConfig().distance
    config.validate()


def test_segmentation_fields_load_from_yaml():
    config = yaml_load_typed(schema=ScanConfig, data=(
        "aim_views: false\nrobot_base_xy: [0.1, -0.2]\ntable_height: 0.75\n"
        "crop_half_size_xy: 0.4\ncap_bottom: false"))
    assert (config.aim_views, config.robot_base_xy, config.table_height) == (
        False, [0.1, -0.2], 0.75)
    assert (config.crop_half_size_xy, config.cap_bottom) == (0.4, False)
    config.validate()


def test_yaml_typo_fails():
    with pytest.raises(RuntimeError, match="num_veiws"):
        yaml_load_typed(schema=ScanConfig, data="num_veiws: 3")


@pytest.mark.parametrize("field, value", [("num_views", 0), ("layout", "helix"),
                                          ("sdf_trunc", 0.001), ("crop_z_max", 0.0),
                                          ("distance_max", 0.3), ("table_tolerance", 0.005),
                                          ("robot_base_xy", [0.0]), ("fov_margin", 0.9),
                                          ("hole_evidence_fraction", 0.0)])
def test_validate_names_the_field(field, value):
    config = ScanConfig(**{field: value})
    with pytest.raises(ValueError, match=f"ScanConfig.{field}"):
        config.validate()
