"""ScanConfig loads with Drake's yaml_load_typed and rejects bad values by field name."""

import pytest
from pydrake.common.yaml import yaml_load_typed

from gbh_drake.perception.config import ScanConfig


def test_loads_from_yaml_with_defaults():
    config = yaml_load_typed(schema=ScanConfig, data="num_views: 1\nnoise: true\nvoxel_size: 0.003")
    assert (config.num_views, config.noise, config.voxel_size) == (1, True, 0.003)
    assert config.distance == ScanConfig().distance
    config.validate()


def test_yaml_typo_fails():
    with pytest.raises(RuntimeError, match="num_veiws"):
        yaml_load_typed(schema=ScanConfig, data="num_veiws: 3")


@pytest.mark.parametrize("field, value", [("num_views", 0), ("layout", "helix"),
                                          ("sdf_trunc", 0.001), ("crop_z_max", 0.0)])
def test_validate_names_the_field(field, value):
    config = ScanConfig(**{field: value})
    with pytest.raises(ValueError, match=f"ScanConfig.{field}"):
        config.validate()
