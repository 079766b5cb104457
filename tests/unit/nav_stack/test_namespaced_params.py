"""A fleet robot's parameter files and remaps (issue 48): `<robot_namespace>` replaced and every section
nested under the robot's namespace, as nav2_bringup's ReplaceString and RewrittenYaml(root_key) do; Jazzy's
nav2_multirobot_params_all.yaml plans and rewrites; topic settings outside the namespace are found."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import yaml

from nav_stack.ros.bringup.bringup_plan import OWNED_SECTIONS, plan_bringup
from nav_stack.ros.bringup.namespaced_params import (
    foreign_topics,
    namespace_remaps,
    namespaced_files,
    namespaced_tree,
    robot_namespace,
)
from nav_stack.ros.bringup.param_files import NavParams

REPO = Path(__file__).resolve().parents[3]
MULTIROBOT = REPO / "config" / "fleet" / "nav2_multirobot_params_all.yaml"
OVERLAY = REPO / "config" / "fleet" / "robot_namespace_overlay.yaml"


def test_sections_nest_under_the_robot_and_placeholders_become_its_namespace() -> None:
    text = ("/**:\n  ros__parameters: {use_sim_time: true}\n"
            "amcl:\n  ros__parameters: {scan_topic: scan}\n"
            "local_costmap:\n  local_costmap:\n    ros__parameters:\n"
            "      obstacle_layer: {scan: {topic: <robot_namespace>/scan}}\n")
    tree = namespaced_tree(text, "/robot2")
    assert tree["/**"] == {"ros__parameters": {"use_sim_time": True}}   # still reaches every node
    assert tree["robot2"]["amcl"] == {"ros__parameters": {"scan_topic": "scan"}}
    scan = tree["robot2"]["local_costmap"]["local_costmap"]["ros__parameters"]["obstacle_layer"]["scan"]
    assert scan == {"topic": "/robot2/scan"}
    with pytest.raises(ValueError, match="expected a map of node names"):
        namespaced_tree("- amcl\n", "/robot2")


def test_robot_namespaces_are_absolute_whatever_slashes_the_name_came_with() -> None:
    assert robot_namespace("robot1") == robot_namespace("/robot1/") == "/robot1"
    with pytest.raises(ValueError, match="must not be empty"):
        robot_namespace("/")


def test_jazzys_multirobot_file_plans_and_reaches_the_namespaced_nodes(tmp_path: Path) -> None:
    plan = plan_bringup([MULTIROBOT])
    assert plan.localization.node_names == ("map_server", "amcl")
    assert {"controller_server", "velocity_smoother", "collision_monitor", "docking_server"} <= set(
        plan.navigation.node_names)
    files = namespaced_files([MULTIROBOT], "/robot1", directory=str(tmp_path))
    try:
        params = NavParams(files)   # read as rcl reads --params-file: fully qualified node names
        assert params.get("robot1/amcl", "scan_topic") == "scan"
        assert params.get("robot1/local_costmap/local_costmap", "voxel_layer.scan.topic") == "/robot1/scan"
        global_scan = params.get("robot1/global_costmap/global_costmap", "obstacle_layer.scan.topic")
        assert global_scan == "/robot1/scan"
        assert params.get("robot1/collision_monitor", "scan.topic") == "/robot1/scan"
        assert not params.configures("amcl")
        assert "<robot_namespace>" not in Path(files[0]).read_text()
    finally:
        for path in files:
            os.unlink(path)


def test_topics_outside_the_namespace_are_found_for_running_nodes_only() -> None:
    plan = plan_bringup([MULTIROBOT])
    running = {*plan.localization.node_names, *plan.navigation.node_names, *OWNED_SECTIONS}
    # Nav2's own file: both absolute names read nothing in a fleet (in Nav2 too)
    assert foreign_topics([MULTIROBOT], "/robot1", running) == [
        "bt_navigator: odom_topic: /odom",
        "collision_monitor: FootprintApproach.footprint_topic: /local_costmap/published_footprint"]
    own = REPO / "config" / "nav2_params.yaml"
    assert foreign_topics([own], "/robot1", running) == [
        "local_costmap/local_costmap: obstacle_layer.scan.topic: /scan",
        "global_costmap/global_costmap: obstacle_layer.scan.topic: /scan"]
    assert foreign_topics([own, OVERLAY], "/robot1", running) == []   # what --robots N runs by default


def test_the_overlay_covers_every_absolute_topic_of_the_robots_own_files(tmp_path: Path) -> None:
    """The shipped robot files and the overlay together name no topic outside the robot's namespace, for
    each model; the overlay itself only sets topics (a change to a robot file shows up here)."""
    for name in ("nav2_params.yaml", "nav2_params_tb4.yaml"):
        files = [REPO / "config" / name, OVERLAY]
        plan = plan_bringup(files)
        running = {*plan.localization.node_names, *plan.navigation.node_names, *OWNED_SECTIONS}
        assert foreign_topics(files, "/robot3", running) == [], name
    flat = NavParams([OVERLAY])
    assert all(key.endswith("topic") for node in flat.nodes for key in flat.section(node))


def test_the_robots_global_topics_are_remapped_into_its_namespace() -> None:
    assert namespace_remaps("/robot2") == ["/tf:=/robot2/tf", "/tf_static:=/robot2/tf_static",
                                           "/diagnostics:=/robot2/diagnostics",
                                           "/trajectories:=/robot2/trajectories"]


def test_the_rewritten_overlay_holds_only_the_robots_costmap_sections(tmp_path: Path) -> None:
    files = namespaced_files([OVERLAY], "/tb4_a", directory=str(tmp_path))
    try:
        tree = yaml.safe_load(Path(files[0]).read_text())
        assert list(tree) == ["tb4_a"] and set(tree["tb4_a"]) == {"local_costmap", "global_costmap"}
    finally:
        os.unlink(files[0])
