"""Core parameter dataclasses bind to ROS parameters with Nav2's spellings and clear errors."""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from rclpy.parameter import Parameter

from nav_stack.ros.common.params import declare_dataclass

pytestmark = pytest.mark.ros


@dataclass(frozen=True)
class Knobs:
    width: float = 3.0
    samples: int = 20
    footprint: tuple[tuple[float, float], ...] = ()
    plugins: tuple[str, ...] = ("a", "b")

    def __post_init__(self) -> None:
        if self.width <= 0:
            raise ValueError(f"width must be positive, got {self.width}")


def make_node(ros_context, overrides: list[Parameter]):
    import rclpy

    return rclpy.create_node("params_probe", context=ros_context, parameter_overrides=overrides)


def test_defaults_ints_for_floats_and_nav2_footprint_strings(ros_context):
    node = make_node(ros_context, [
        Parameter("width", value=4),  # YAML `width: 4` arrives as an int
        Parameter("footprint", value="[[0.2, 0.1], [-0.2, 0.1], [-0.2, -0.1], [0.2, -0.1]]"),
    ])
    try:
        knobs = declare_dataclass(node, Knobs)
        assert knobs.width == 4.0 and isinstance(knobs.width, float)
        assert knobs.samples == 20
        assert knobs.footprint == ((0.2, 0.1), (-0.2, 0.1), (-0.2, -0.1), (0.2, -0.1))
        assert knobs.plugins == ("a", "b")
    finally:
        node.destroy_node()


def test_prefix_and_invalid_value_names_node_parameter_and_value(ros_context):
    node = make_node(ros_context, [Parameter("FollowPath.width", value=-1.0)])
    try:
        with pytest.raises(ValueError, match=r"params_probe: invalid parameters for Knobs: width must be "
                                             r"positive, got -1.0 .*FollowPath.width=-1.0"):
            declare_dataclass(node, Knobs, prefix="FollowPath.")
    finally:
        node.destroy_node()


def test_a_malformed_footprint_string_names_the_node_and_the_parameter():
    from nav_stack.ros.costmap.costmap_params import parse_footprint

    triangle = parse_footprint("[[0.1, 0.2], [0.1, -0.2], [-0.1, 0.0]]", "n")
    assert triangle == ((0.1, 0.2), (0.1, -0.2), (-0.1, 0.0))
    assert parse_footprint("[]", "n") == ()
    with pytest.raises(ValueError, match=r"controller_server: parameter collision_footprint must look like"):
        parse_footprint("[[0.1, 0.2], [oops", "controller_server", "collision_footprint")
