"""A Nav2 client works unchanged: the calls nav2_simple_commander's BasicNavigator makes (Jazzy),
over the same interfaces, against the stack started by nav-bringup.

BasicNavigator is not on pip (and its source may not be copied here), so ``MiniNavigator``
(tests/helpers/mini_navigator.py) repeats its protocol (dockRobotByID and undockRobot included):
waitUntilNav2Active polls ``amcl/get_state`` until "active", publishes /initialpose until
/amcl_pose arrives, then polls ``bt_navigator/get_state``; tasks are judged by GoalStatus only, as
BasicNavigator does.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration
from nav2_msgs.action import (
    BackUp,
    ComputePathToPose,
    DockRobot,
    FollowWaypoints,
    NavigateThroughPoses,
    NavigateToPose,
    Spin,
    UndockRobot,
)
from nav2_msgs.srv import ClearEntireCostmap, GetCostmap, LoadMap
from rclpy.executors import SingleThreadedExecutor

from navsuite_testing.ros import REPO, BackgroundSpin
from tests.helpers.mini_navigator import MiniNavigator
from tests.helpers.mini_navigator import pose_stamped as _pose
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait

pytestmark = [pytest.mark.ros, pytest.mark.slow]


@pytest.fixture(scope="module", params=["one-process", "isolated"])
def stack(request: Any) -> Iterator[Bringup]:
    """The stack in both layouts: one nav2 process (the default) and ``--isolated``, with
    turtlebot3_world's dock database (docs/docking.md), so docking_server runs too."""
    layout = ["--isolated"] if request.param == "isolated" else []
    bringup = Bringup("--no-initial-pose", *layout, "--params", str(REPO / "config" / "nav2_params.yaml"),
                      "--params", str(REPO / "config" / "docks" / "turtlebot3_world.yaml"))
    try:
        bringup.wait_for_line(READY, timeout=240.0)
        yield bringup
    finally:
        bringup.stop()


@pytest.fixture
def nav(stack, ros_context) -> Iterator[MiniNavigator]:
    navigator = MiniNavigator(ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(navigator.node)
    spin = BackgroundSpin(executor)
    try:
        navigator.set_initial_pose(-2.0, -0.5)  # turtlebot3_world's spawn
        yield navigator
    finally:
        print(stack.output(200))  # shown by pytest when the test fails
        spin.stop(navigator.node)


def test_basic_navigator_session(nav):
    nav.wait_until_nav2_active()

    nav.start("compute_path_to_pose", ComputePathToPose.Goal(goal=_pose(0.55, 0.0), use_start=False))
    planned = nav.result().result
    path = planned.path
    assert len(path.poses) > 10 and path.header.frame_id == "map", (planned.error_code, planned.error_msg)

    nav.start("navigate_to_pose", NavigateToPose.Goal(pose=_pose(-0.55, -1.65)))
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED

    nav.start("spin", Spin.Goal(target_yaw=1.57, time_allowance=Duration(sec=10)))  # spin() defaults
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED
    backup = BackUp.Goal(speed=0.1, time_allowance=Duration(sec=10))  # backup(0.15, 0.1, 10) defaults
    backup.target.x = 0.15
    nav.start("backup", backup)
    assert nav.result().status in (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_ABORTED)

    through = NavigateThroughPoses.Goal(poses=[_pose(0.55, -1.65), _pose(0.55, 0.0, 1.57)])
    nav.start("navigate_through_poses", through)
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED

    nav.start("follow_waypoints", FollowWaypoints.Goal(poses=[_pose(0.55, 1.0), _pose(-0.55, 1.65)]))
    result = nav.result()
    assert result.status == GoalStatus.STATUS_SUCCEEDED and not result.result.missed_waypoints

    nav.start("navigate_to_pose", NavigateToPose.Goal(pose=_pose(-2.0, -0.5)))
    wait(lambda: nav.handle.status == GoalStatus.STATUS_EXECUTING, 30.0, "the navigation to run")
    nav.cancel_task()
    assert nav.result().status == GoalStatus.STATUS_CANCELED

    for costmap in ("global_costmap", "local_costmap"):  # clearAllCostmaps
        nav.call(ClearEntireCostmap, f"{costmap}/clear_entirely_{costmap}", ClearEntireCostmap.Request())
    costmap = nav.call(GetCostmap, "global_costmap/get_costmap", GetCostmap.Request()).map  # getGlobalCostmap
    size = costmap.metadata.size_x * costmap.metadata.size_y
    assert size > 0 and len(costmap.data) == size

    # dockRobotByID(dock_id, nav_to_dock=True), then undockRobot(dock_type=''): the server knows the type
    nav.start("dock_robot", DockRobot.Goal(use_dock_id=True, dock_id="home_dock",
                                           navigate_to_staging_pose=True))
    docked = nav.result()
    assert docked.status == GoalStatus.STATUS_SUCCEEDED, (docked.result.error_code, docked.result.error_msg)
    nav.start("undock_robot", UndockRobot.Goal(dock_type=""))
    undone = nav.result()
    assert undone.status == GoalStatus.STATUS_SUCCEEDED, (undone.result.error_code, undone.result.error_msg)

    url = f"file://{REPO / 'maps' / 'turtlebot3_world.yaml'}"
    response = nav.call(LoadMap, "map_server/load_map", LoadMap.Request(map_url=url))  # changeMap
    assert response.result == LoadMap.Response.RESULT_SUCCESS
