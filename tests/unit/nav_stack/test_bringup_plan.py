"""nav-bringup's plan from Nav2 parameter files: lifecycle lists as nav2_bringup's launch files, the
cmd_vel chain, and one refusal that lists every setting the stack cannot run."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from nav_stack.ros.bringup.bringup_plan import cmd_vel_remaps, plan_bringup
from nav_stack.ros.bringup.config_check import ConfigError
from nav_stack.ros.bringup.param_files import NavParams, ParamFileError
from nav_stack.ros.bringup.plugin_catalog import NAVIGATION_NODES

REPO = Path(__file__).resolve().parents[3]
JAZZY = REPO / "config" / "jazzy" / "nav2_params.yaml"


def write(tmp_path: Path, name: str, tree: dict) -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(tree))
    return path


def section(**params: object) -> dict:
    return {"ros__parameters": params}


def test_param_files_merge_in_order_flatten_and_apply_wildcards(tmp_path: Path) -> None:
    base = write(tmp_path, "base.yaml", {
        "/**": section(use_sim_time=True),
        "controller_server": section(controller_frequency=20.0, FollowPath={"plugin": "a::A", "k": 1}),
        "local_costmap": {"local_costmap": section(width=3)},
    })
    overlay = write(tmp_path, "overlay.yaml", {"controller_server": section(FollowPath={"k": 2})})
    params = NavParams([base, overlay])
    assert params.get("controller_server", "FollowPath.plugin") == "a::A"
    assert params.get("controller_server", "FollowPath.k") == 2
    assert params.where("controller_server", "FollowPath.k") == overlay
    assert params.get("controller_server", "use_sim_time") is True
    assert params.get("local_costmap/local_costmap", "width") == 3
    assert params.configures("controller_server") and not params.configures("planner_server")
    assert params.section_file("controller_server") == base


def test_a_broken_param_file_names_the_file(tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text("controller_server: [unclosed\n")
    with pytest.raises(ParamFileError, match=r"broken\.yaml: not valid YAML"):
        NavParams([broken])
    with pytest.raises(ParamFileError, match=r"missing\.yaml: cannot read it"):
        NavParams([tmp_path / "missing.yaml"])


def test_without_lifecycle_sections_bringup_chooses_nav2_bringups_lists(tmp_path: Path) -> None:
    """The hang of issue 41: a Nav2 user's file has no lifecycle sections; bringup supplies them."""
    plain = write(tmp_path, "plain.yaml", {"controller_server": section(controller_frequency=20.0)})
    plan = plan_bringup([plain])
    assert plan.localization.node_names == ("map_server", "amcl")
    assert plan.localization.autostart and plan.navigation.autostart
    assert plan.navigation.node_names == ("controller_server", "planner_server", "behavior_server",
                                          "bt_navigator", "waypoint_follower")
    assert plan.remaps == ()


def test_a_files_own_lifecycle_section_overrides_bringups_choice(tmp_path: Path) -> None:
    own = write(tmp_path, "own.yaml", {"lifecycle_manager_navigation": section(
        node_names=["planner_server", "controller_server"], autostart=False)})
    plan = plan_bringup([own])
    assert plan.navigation.node_names == ("planner_server", "controller_server")
    assert not plan.navigation.autostart


def test_slam_leaves_localization_out(tmp_path: Path) -> None:
    plain = write(tmp_path, "plain.yaml", {"lifecycle_manager_localization": section(node_names=["amcl"])})
    assert plan_bringup([plain], slam=True).localization.node_names == ()


def test_every_problem_is_listed_with_file_section_key_value_and_supported_values(tmp_path: Path) -> None:
    bad = write(tmp_path, "bad.yaml", {
        "controller_server": section(controller_plugins=["FollowPath"],
                                     FollowPath={"plugin": "my_pkg::MyController"}),
        "planner_server": section(planner_plugins=["GridBased", "Smac"],
                                  Smac={"plugin": "nav2_smac_planner/Hybrid"}),
        "global_costmap": {"global_costmap": section(plugins=["static_layer", "keepout"],
                                                     keepout={"plugin": "nav2_costmap_2d::KeepoutFilter"})},
        "lifecycle_manager_navigation": section(
            node_names=["controller_server", "planner_server", "route_server"]),
    })
    with pytest.raises(ConfigError) as caught:
        plan_bringup([bad])
    message = str(caught.value)
    assert len(caught.value.problems) == 4, message
    for expected in (
        "bad.yaml: controller_server: FollowPath.plugin: 'my_pkg::MyController' is not a plugin this "
        "stack has (supported: DWBLocalPlanner",
        "planner_server: Smac.plugin: 'nav2_smac_planner/Hybrid'",
        "global_costmap/global_costmap: keepout.plugin: 'nav2_costmap_2d::KeepoutFilter'",
        "lifecycle_manager_navigation: node_names: 'route_server' is not a server this stack has",
    ):
        assert expected in message


def test_jazzys_file_is_planned_with_every_server_of_its_launch_file() -> None:
    """Jazzy's own file, unmodified: nothing refused, and every navigation server it configures runs,
    in nav2_bringup's order."""
    plan = plan_bringup([JAZZY])
    assert plan.navigation.node_names == NAVIGATION_NODES
    assert plan.localization.node_names == ("map_server", "amcl")
    assert any("route_server: not started" in note for note in plan.notes)


@pytest.mark.parametrize(("nodes", "expected"), [
    (("controller_server", "behavior_server", "velocity_smoother", "collision_monitor"),
     {"velocity_smoother:cmd_vel:=cmd_vel_nav", "controller_server:cmd_vel:=cmd_vel_nav",
      "behavior_server:cmd_vel:=cmd_vel_nav"}),
    (("controller_server", "velocity_smoother"),
     {"velocity_smoother:cmd_vel:=cmd_vel_nav", "velocity_smoother:cmd_vel_smoothed:=cmd_vel",
      "controller_server:cmd_vel:=cmd_vel_nav"}),
    (("controller_server", "docking_server", "collision_monitor"),
     {"controller_server:cmd_vel:=cmd_vel_smoothed"}),
    (("controller_server",), set()),
])
def test_the_velocity_chain_always_ends_on_cmd_vel(tmp_path: Path, nodes: tuple[str, ...],
                                                   expected: set[str]) -> None:
    monitor = section(cmd_vel_in_topic="cmd_vel_smoothed")
    params = NavParams([write(tmp_path, "p.yaml", {"collision_monitor": monitor})])
    assert set(cmd_vel_remaps(nodes, params)) == expected


def test_the_project_files_leave_the_lists_to_bringup_and_an_overlay_adds_its_server() -> None:
    """The shipped files have no node_names (as Nav2's), so an overlay that configures an optional
    server (a dock database, a collision monitor) gets it started without repeating the list."""
    config = REPO / "config"
    base = ("controller_server", "planner_server", "behavior_server", "bt_navigator", "waypoint_follower")
    for robot_file in (config / "nav2_params.yaml", config / "nav2_params_tb4.yaml"):
        plan = plan_bringup([robot_file])
        assert plan.navigation.node_names == base
        assert plan.localization.node_names == ("map_server", "amcl")
        assert plan.navigation.autostart and plan.localization.autostart
    docked = plan_bringup([config / "nav2_params.yaml", config / "docks" / "turtlebot3_world.yaml"])
    assert docked.navigation.node_names == (*base, "docking_server")
    monitor = config / "scenarios" / "collision_monitor_params.yaml"
    guarded = plan_bringup([config / "nav2_params.yaml", monitor])
    assert guarded.navigation.node_names == (*base[:3], "collision_monitor", *base[3:])
