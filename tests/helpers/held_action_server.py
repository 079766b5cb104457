"""A NavigateToPose server in a process of its own that accepts every goal and never ends one: the
server a test kills (SIGKILL) and starts again, to see a client notice that its goal's server is gone.

``python -m tests.helpers.held_action_server`` prints ``held server ready`` once it serves, then spins
until killed. Every goal stays executing for ever (its execute coroutine awaits a future that never
completes), as a goal whose navigator died never gets a result.
"""

from __future__ import annotations

from typing import Any

READY_LINE = "held server ready"


def main() -> None:
    import rclpy
    from nav2_msgs.action import NavigateToPose
    from rclpy.node import Node
    from rclpy.task import Future

    from ros_tools.runtime.actions import ActionServer

    rclpy.init()
    node = Node("held_navigator")

    async def execute(_goal: Any) -> Any:
        await Future()  # never done: the goal holds until the process dies
        return NavigateToPose.Result()

    ActionServer(node, NavigateToPose, "navigate_to_pose", execute)
    print(READY_LINE, flush=True)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
