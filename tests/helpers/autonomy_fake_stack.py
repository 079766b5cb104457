"""A stand-in for ``nav-bringup`` in demo tests: FakeNav2 plus a battery that drains away from the
station and charges at it (sim time), printing "Nav2 is ready" like the real stack.

Battery model (fractions of a full charge), like sim2d's but deterministic with FakeNav2's instant
(teleporting) navigation: −``drain`` per metre the robot moved, +``charge`` per sim s while it is
within 0.4 m of the seed's station (-1.37, -0.82).
"""

from __future__ import annotations

import argparse
import math

from ros_tools.dds import keep_dds_local


def main() -> int:
    keep_dds_local()
    import rclpy
    from rclpy.context import Context
    from sensor_msgs.msg import BatteryState

    from tests.helpers.smacc_ros_fake_nav2 import FakeNav2, serve_until_signalled

    parser = argparse.ArgumentParser()
    parser.add_argument("--rtf", type=float, default=10.0)
    parser.add_argument("--drain", type=float, default=0.15)
    parser.add_argument("--charge", type=float, default=0.5)
    options = parser.parse_args()
    context = Context()
    rclpy.init(context=context)
    fake = FakeNav2(context, clock_rate=options.rtf)
    state: dict[str, object] = {"level": 1.0, "t": None, "at": None}
    pub = fake.node.create_publisher(BatteryState, "/battery_state", 10)

    def battery() -> None:
        now = fake.sim_s
        x, y, _ = fake.map_pose()
        last_t, last_at = state["t"], state["at"]
        dt = 0.0 if last_t is None else now - float(last_t)  # type: ignore[arg-type]
        relocalised = len(fake.initial_poses) != state.get("resets", 0)  # /initialpose moved map->odom
        moved = 0.0 if last_at is None or relocalised else math.dist((x, y), last_at)  # type: ignore[arg-type]
        state["t"], state["at"], state["resets"] = now, (x, y), len(fake.initial_poses)
        docked = math.hypot(x + 1.37, y + 0.82) <= 0.4
        change = options.charge * dt if docked else -options.drain * moved
        state["level"] = min(1.0, max(0.0, float(state["level"]) + change))  # type: ignore[arg-type]
        pub.publish(BatteryState(percentage=float(state["level"])))  # type: ignore[arg-type]

    fake.node.create_timer(0.02, battery)
    fake.start()
    return serve_until_signalled(fake, context, "fake stack with battery up; Nav2 is ready")


if __name__ == "__main__":
    raise SystemExit(main())
