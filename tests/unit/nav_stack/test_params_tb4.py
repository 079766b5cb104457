"""config/nav2_params_tb4.yaml is config/nav2_params.yaml with only the TurtleBot4's keys changed.

Why: the two files are copies; a tuning made in one and forgotten in the other would make the robots
behave differently for no reason. A key that must differ is listed here with its TB4 value, and
checked against sim2d's TB4 model (the data both packages share; nav_stack itself never imports sim2d).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from nav_stack.ros.bringup.robot_params import ROBOTS, params_for_robot
from sim2d.core import robot as sim_robots

CONFIG = Path(__file__).resolve().parents[3] / "config"
ROBOT_RADIUS = "ros__parameters.robot_radius"
RADIUS_KEYS = (f"local_costmap.local_costmap.{ROBOT_RADIUS}", f"global_costmap.global_costmap.{ROBOT_RADIUS}")
#: dotted key -> the TB4's value; every other key must equal nav2_params.yaml's.
TB4_KEYS: dict[str, Any] = {
    RADIUS_KEYS[0]: 0.175,
    RADIUS_KEYS[1]: 0.175,
    "controller_server.ros__parameters.collision_footprint": "[]",
    "controller_server.ros__parameters.FollowPath.desired_linear_vel": 0.30,
    "controller_server.ros__parameters.DWB.max_vel_x": 0.30,
    "controller_server.ros__parameters.DWB.max_speed_xy": 0.30,
    "amcl.ros__parameters.laser_max_range": 12.0,
    "slam.ros__parameters.max_laser_range": 12.0,
}


def _flat(node: Any, prefix: str = "") -> dict[str, Any]:
    if not isinstance(node, dict):
        return {prefix.rstrip("."): node}
    out: dict[str, Any] = {}
    for key, value in node.items():
        out.update(_flat(value, f"{prefix}{key}."))
    return out


def _load(name: str) -> dict[str, Any]:
    return _flat(yaml.safe_load((CONFIG / name).read_text()))


def test_the_tb4_file_differs_only_in_the_listed_keys() -> None:
    base, tb4 = _load("nav2_params.yaml"), _load("nav2_params_tb4.yaml")
    assert set(tb4) == set(base), "keys added or removed in only one file"
    differing = {key: tb4[key] for key in base if tb4[key] != base[key]}
    assert differing == TB4_KEYS


def test_the_tb4_values_fit_sim2ds_tb4() -> None:
    tb4, model = _load("nav2_params_tb4.yaml"), sim_robots.TB4
    for key in RADIUS_KEYS:
        assert tb4[key] >= model.bounding_radius()   # the costmaps keep all of the body off obstacles
    assert tb4["controller_server.ros__parameters.FollowPath.desired_linear_vel"] <= model.max_linear_velocity
    assert tb4["controller_server.ros__parameters.FollowPath.rotate_to_heading_angular_vel"] <= \
        model.max_angular_velocity
    assert tb4["amcl.ros__parameters.laser_max_range"] == model.lidar.range_max
    assert tb4["slam.ros__parameters.max_laser_range"] == model.lidar.range_max


def test_every_sim2d_robot_has_a_parameter_file() -> None:
    assert set(ROBOTS) == set(sim_robots.ROBOTS)
    assert params_for_robot("tb4") == CONFIG / "nav2_params_tb4.yaml"
    assert params_for_robot("waffle") == params_for_robot("burger") == CONFIG / "nav2_params.yaml"
    with pytest.raises(ValueError, match="unknown model 'kobuki'"):
        params_for_robot("kobuki")
