"""collision_monitor's decision (Nav2 Jazzy): zones (polygon, circle), each action type's output, the
most restrictive polygon winning, the invalid-source stop, the state change and stop_pub_timeout,
and the parameter checks."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import pytest

from nav_stack.core.collision_monitor import (
    INVALID_SOURCE,
    ZERO,
    ActionType,
    CollisionMonitor,
    CollisionMonitorParams,
    PolygonParams,
    SourceParams,
    Velocity,
    Zone,
    decide,
    parse_points,
)

SQUARE = "[[0.5, 0.3], [0.5, -0.3], [0.0, -0.3], [0.0, 0.3]]"  # 0.5 x 0.6 m ahead of the base
FORWARD = Velocity(0.3, 0.0, 0.4)


def zone(name: str, action_type: str, points: str = SQUARE, **fields: Any) -> Zone:
    return Zone(name, PolygonParams(type="polygon", action_type=action_type, points=points,
                                    min_points=fields.pop("min_points", 1), **fields))


def cloud(*xy: tuple[float, float]) -> dict[str, np.ndarray]:
    return {"scan": np.array(xy, dtype=np.float64).reshape(-1, 2)}


OBSTACLE_AHEAD = cloud((0.3, 0.0))  # inside SQUARE
FREE = cloud((2.0, 0.0), (-1.0, 0.5))


# -- zones ---------------------------------------------------------------------------------------
def test_a_polygon_counts_the_points_inside_by_the_crossing_rule() -> None:
    z = zone("z", "stop")
    pts = np.array([[0.25, 0.0], [0.49, 0.29], [0.51, 0.0], [0.25, 0.31], [-0.01, 0.0], [0.25, -0.29]])
    assert z.inside(pts).tolist() == [True, True, False, False, False, True]
    concave = zone("u", "stop", points="[[0, 0], [1, 0], [1, 1], [0.6, 1], [0.6, 0.3], [0.4, 0.3], "
                                       "[0.4, 1], [0, 1]]")
    assert concave.inside(np.array([[0.5, 0.8], [0.2, 0.8], [0.5, 0.1]])).tolist() == [False, True, True]


def test_a_circle_counts_points_strictly_within_its_radius() -> None:
    c = Zone("c", PolygonParams(type="circle", action_type="stop", radius=0.5))
    pts = np.array([[0.3, 0.3], [0.5, 0.0], [0.0, -0.49], [0.36, 0.36]])
    assert c.inside(pts).tolist() == [True, False, True, False]
    assert c.outline is not None and len(c.outline) == 16
    assert np.allclose(np.hypot(*c.outline.T), 0.5)


def test_min_points_is_the_trigger_threshold_and_max_points_its_deprecated_form() -> None:
    z = zone("z", "stop", min_points=3)
    assert not z.triggered(np.array([[0.1, 0.0], [0.2, 0.0], [3.0, 0.0]]))
    assert z.triggered(np.array([[0.1, 0.0], [0.2, 0.0], [0.3, 0.0]]))
    assert zone("z", "stop", min_points=4, max_points=1).min_points == 2


def test_a_dynamic_zone_is_unset_until_a_shape_arrives_and_refuses_fewer_than_3_points() -> None:
    z = Zone("dyn", PolygonParams(type="polygon", action_type="stop", polygon_sub_topic="zone", min_points=1))
    assert z.dynamic and not z.is_set
    assert decide(FORWARD, [z], OBSTACLE_AHEAD).action_type == ActionType.DO_NOTHING  # skipped, not an error
    with pytest.raises(ValueError, match="at least 3 points, got 2"):
        z.set_shape([[0.0, 0.0], [1.0, 0.0]])
    z.set_shape([[0.5, 0.3], [0.5, -0.3], [0.0, -0.3], [0.0, 0.3]])
    assert decide(FORWARD, [z], OBSTACLE_AHEAD).action_type == ActionType.STOP


# -- each action type ----------------------------------------------------------------------------
def test_stop_sends_zero_and_names_the_polygon() -> None:
    action = decide(FORWARD, [zone("PolygonStop", "stop")], OBSTACLE_AHEAD)
    assert (action.action_type, action.velocity) == (ActionType.STOP, ZERO)
    assert action.polygon_name == "PolygonStop"


def test_slowdown_scales_the_whole_command_by_its_ratio() -> None:
    action = decide(FORWARD, [zone("Slow", "slowdown", slowdown_ratio=0.3)], OBSTACLE_AHEAD)
    assert action.action_type == ActionType.SLOWDOWN
    assert action.velocity == pytest.approx((0.09, 0.0, 0.12))


def test_limit_caps_the_linear_speed_keeping_its_direction_and_clamps_the_turn() -> None:
    z = zone("Limit", "limit", linear_limit=0.1, angular_limit=0.2)
    action = decide(Velocity(0.3, 0.4, -0.5), [z], OBSTACLE_AHEAD)
    assert action.action_type == ActionType.LIMIT
    assert action.velocity == pytest.approx((0.06, 0.08, -0.2))  # |v| 0.5 → 0.1 along (0.6, 0.8)
    slow = decide(Velocity(0.05, 0.0, 0.1), [z], OBSTACLE_AHEAD)
    assert slow.action_type == ActionType.DO_NOTHING  # already within the limits: not slower


def test_nothing_inside_passes_the_command_unchanged() -> None:
    zones = [zone("Stop", "stop"), zone("Slow", "slowdown")]
    action = decide(FORWARD, zones, FREE)
    assert (action.action_type, action.velocity, action.polygon_name) == (ActionType.DO_NOTHING, FORWARD, "")


def test_a_zero_command_passes_through_as_zero() -> None:
    for z in (zone("Slow", "slowdown"), zone("Limit", "limit")):
        action = decide(ZERO, [z], OBSTACLE_AHEAD)
        assert (action.velocity, action.action_type) == (ZERO, ActionType.DO_NOTHING)
    assert decide(ZERO, [zone("Stop", "stop")], OBSTACLE_AHEAD).velocity == ZERO


# -- the most restrictive wins -------------------------------------------------------------------
def test_the_slowest_result_wins_by_nav2s_measure_and_stop_beats_everything() -> None:
    slow = zone("Slow", "slowdown", slowdown_ratio=0.5)
    limit = zone("Limit", "limit", linear_limit=0.05, angular_limit=0.05)
    gentle = zone("Gentle", "slowdown", slowdown_ratio=0.9)
    assert decide(FORWARD, [gentle, slow, limit], OBSTACLE_AHEAD).polygon_name == "Limit"
    assert decide(FORWARD, [limit, slow, gentle], OBSTACLE_AHEAD).polygon_name == "Limit"
    stop = zone("Stop", "stop")
    assert decide(FORWARD, [slow, limit, stop], OBSTACLE_AHEAD).polygon_name == "Stop"
    far = zone("Far", "stop", points="[[3, 1], [3, -1], [2.5, -1], [2.5, 1]]")
    assert decide(FORWARD, [far, slow], OBSTACLE_AHEAD).polygon_name == "Slow"  # only zones that hold points


def test_a_disabled_zone_and_a_zone_reading_other_sources_do_not_act() -> None:
    off = zone("Stop", "stop", enabled=False)
    assert decide(FORWARD, [off], OBSTACLE_AHEAD).action_type == ActionType.DO_NOTHING
    lidar_only = zone("Stop", "stop", sources_names=("lidar",))
    assert decide(FORWARD, [lidar_only], OBSTACLE_AHEAD).action_type == ActionType.DO_NOTHING
    assert decide(FORWARD, [lidar_only], {"lidar": np.array([[0.3, 0.0]])}).action_type == ActionType.STOP


def test_an_invalid_source_stops_the_robot_before_any_polygon() -> None:
    action = decide(FORWARD, [zone("Slow", "slowdown")], None)
    assert (action.action_type, action.velocity) == (ActionType.STOP, ZERO)
    assert action.polygon_name == INVALID_SOURCE == "invalid source"


# -- state and stop publication ------------------------------------------------------------------
def test_the_state_changes_with_the_polygon_and_zero_is_published_for_stop_pub_timeout() -> None:
    params = CollisionMonitorParams(polygons=("Stop",), observation_sources=("scan",), stop_pub_timeout=1.0)
    monitor = CollisionMonitor(params, [zone("Stop", "stop")])
    first = monitor.process(FORWARD, FREE, 10.0)
    assert first.publish and not first.state_changed  # "" → "": nothing to report
    stopped = monitor.process(FORWARD, OBSTACLE_AHEAD, 10.1)
    assert stopped.publish and stopped.state_changed and stopped.action.velocity == ZERO
    assert [monitor.process(FORWARD, OBSTACLE_AHEAD, t).publish for t in (10.6, 11.1, 11.11, 12.0)] == [
        True, True, False, False]  # zeros for 1 s after the stop, then silence
    again = monitor.process(FORWARD, FREE, 12.1)
    assert again.publish and again.state_changed and again.action.velocity == FORWARD
    assert monitor.process(ZERO, FREE, 12.2).publish  # the input itself stopping: a new stop stamp
    assert monitor.process(ZERO, FREE, 13.2).publish and not monitor.process(ZERO, FREE, 13.3).publish


def test_the_first_zero_command_is_published_and_a_reset_forgets_the_stop() -> None:
    params = CollisionMonitorParams(polygons=("Stop",), observation_sources=("scan",))
    monitor = CollisionMonitor(params, [zone("Stop", "stop")])
    assert monitor.process(ZERO, FREE, 5.0).publish
    assert not monitor.process(ZERO, FREE, 7.0).publish
    monitor.reset()
    assert monitor.process(ZERO, FREE, 8.0).publish


# -- parameters ----------------------------------------------------------------------------------
def test_points_are_jazzys_string_of_pairs() -> None:
    assert parse_points(SQUARE) == ((0.5, 0.3), (0.5, -0.3), (0.0, -0.3), (0.0, 0.3))
    assert len(parse_points("[[0, 0], [1, 0], [0, 1]]")) == 3
    with pytest.raises(ValueError, match=r"points = '\[\[0, 0\], \[1, 0\]\]': a polygon needs at least 3"):
        parse_points("[[0, 0], [1, 0]]")
    with pytest.raises(ValueError, match="must look like"):
        parse_points("[0.3, 0.3, 0.3, -0.3, 0.0, -0.3]")  # the Humble/Iron flat form


@pytest.mark.parametrize(("fields", "message"), [
    ({"type": "hexagon", "action_type": "stop", "points": SQUARE},
     "type = 'hexagon': must be one of polygon, circle"),
    ({"type": "velocity_polygon", "action_type": "stop", "points": SQUARE},
     "type = 'velocity_polygon' (a Jazzy type not implemented here)"),
    ({"type": "polygon", "action_type": "explode", "points": SQUARE}, "action_type = 'explode'"),
    ({"type": "polygon", "action_type": "stop", "points": "[[0, 0], [1, 1]]"}, "at least 3 points, got 2"),
    ({"type": "polygon", "action_type": "stop"}, "points = '' and polygon_sub_topic = ''"),
    ({"type": "circle", "action_type": "stop"}, "radius = 0.0: must be > 0"),
    ({"type": "polygon", "action_type": "slowdown", "points": SQUARE, "slowdown_ratio": 1.5},
     "slowdown_ratio = 1.5"),
    ({"type": "polygon", "action_type": "approach", "points": SQUARE, "simulation_time_step": 0.0},
     "simulation_time_step = 0.0"),
])
def test_bad_polygon_parameters_are_refused_naming_the_parameter_and_value(fields: dict[str, Any],
                                                                         message: str) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        PolygonParams(**fields)


def test_an_approach_polygon_defaults_to_the_local_costmaps_footprint() -> None:
    p = PolygonParams(type="polygon", action_type="approach")
    assert p.footprint_topic == "local_costmap/published_footprint" and Zone("A", p).dynamic


def test_bad_node_and_source_parameters_are_refused() -> None:
    with pytest.raises(ValueError, match=re.escape("polygons = []: must name at least one")):
        CollisionMonitorParams(observation_sources=("scan",))
    with pytest.raises(ValueError, match=r"source_timeout = -1\.0"):
        CollisionMonitorParams(polygons=("a",), observation_sources=("scan",), source_timeout=-1.0)
    with pytest.raises(ValueError, match="topic = '': a source needs a topic"):
        SourceParams(topic="")
    with pytest.raises(ValueError, match=re.escape("type = 'range' (a Jazzy type not implemented here)")):
        SourceParams(type="range")
    assert SourceParams().source_timeout == 2.0 and not math.isnan(SourceParams().min_height)
