"""Notice that the navigation process died under a running goal, and when its respawn is back.

Why: a NavigateToPose goal lives in bt_navigator's process. When nav-bringup respawns that process
(its ``use_respawn``), the new bt_navigator knows nothing of the old goal and the client would wait
for ever for a result; DDS tells nobody, as a killed participant stays in the graph until its lease
runs out (seconds, and meanwhile the new server carries the same names). The lockstep reports
already name the process (``<role>:<pid>``, navsuite_tools.scenarios.navigation_kill), so the goal driver
checks that pid on this machine: a dead pid ends the goal, and the first report of a new pid says
the respawned stack is active (a component reports only once its lifecycle managers are).

While the stack is away the simulator does not run on: the dead process's role is one sim2d expects,
so its lockstep gate holds the world until a new process of that role joins (sim2d/core/lockstep.py).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from navsuite_tools.scenarios.navigation_kill import navigation_pid
from navsuite_tools.scenarios.process_faults import process_exists

#: wall s after the new process reported, without /amcl_pose, before a goal is sent anyway
POSE_WAIT_LIMIT = 10.0


class NavigationWatch:
    """Follows the navigation process's pid on /lockstep/progress and AMCL's poses on /amcl_pose."""

    def __init__(self, node: Any, alive: Callable[[int], bool] = process_exists) -> None:
        from geometry_msgs.msg import PoseWithCovarianceStamped
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from std_msgs.msg import Header

        from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC

        self.pid: int | None = None  # the navigation process's pid, once a report named it
        self.lives = 0  # navigation processes seen (1 before any respawn)
        self._alive = alive
        self._pose_wall = -1.0  # monotonic s of the last /amcl_pose
        self._back_wall = -1.0  # monotonic s of the first report of the current process
        node.create_subscription(Header, PROGRESS_TOPIC, self._on_progress, PROGRESS_QOS)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node.create_subscription(PoseWithCovarianceStamped, "amcl_pose", self._on_pose, latched)

    def _on_progress(self, msg: Any) -> None:
        pid = navigation_pid(msg.frame_id)
        if pid is None or pid == self.pid or (msg.stamp.sec == 0 and msg.stamp.nanosec == 0):
            return  # not navigation, the same process, or a leave
        if self.pid is None or not self._alive(self.pid):
            self.pid, self.lives, self._back_wall = pid, self.lives + 1, time.monotonic()

    def _on_pose(self, _msg: Any) -> None:
        self._pose_wall = time.monotonic()

    def dead(self) -> int | None:
        """The pid of the navigation process when it is gone, else None."""
        return self.pid if self.pid is not None and not self._alive(self.pid) else None

    def back(self, dead_pid: int) -> bool:
        """Whether a new navigation process replaced ``dead_pid``, is active, and AMCL has a pose
        again (or POSE_WAIT_LIMIT passed: a stack without AMCL, e.g. SLAM, sends none)."""
        if self.pid is None or self.pid == dead_pid or not self._alive(self.pid):
            return False
        now = time.monotonic()
        return self._pose_wall >= self._back_wall or now - self._back_wall > POSE_WAIT_LIMIT
