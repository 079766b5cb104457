"""``smacc-key <key> [--topic /keyboard_unicode]``: press a key for a running state machine.

Publishes the key's code point as std_msgs/UInt16, like SMACC2's keyboard_server_node, after waiting
(up to ``--wait`` s) for a subscriber so the key is not lost; exits 1 when nobody listens or the
subscriber does not acknowledge the key within ``--wait`` s.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from typing import Any


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="smacc-key", description=__doc__.splitlines()[0])
    parser.add_argument("key", help="one character, e.g. n")
    parser.add_argument("--topic", default="/keyboard_unicode")
    parser.add_argument("--wait", type=float, default=5.0, help="seconds to wait for a subscriber")
    options = parser.parse_args(argv)
    if len(options.key) != 1:
        print(f"smacc-key: give exactly one character, got {options.key!r}", file=sys.stderr)
        return 2
    import rclpy
    from rclpy.duration import Duration
    from std_msgs.msg import UInt16

    from ros_tools.runtime.runner import run_nodes

    publishers: list[Any] = []
    deadline: list[float] = []  # time.monotonic() after which nobody listening is an error

    def build() -> list[Any]:
        node = rclpy.create_node("smacc_key")
        publishers.append(node.create_publisher(UInt16, options.topic, 10))
        deadline.append(time.monotonic() + options.wait)
        return [node]

    def finished(nodes: Sequence[Any]) -> int | None:
        """Checked between spins: send the key once a subscriber shows, then wait for its ack."""
        publisher = publishers[0]
        if publisher.get_subscription_count() == 0:
            if time.monotonic() <= deadline[0]:
                return None
            print(f"smacc-key: nobody subscribes {options.topic} (waited {options.wait:.0f} s)",
                  file=sys.stderr)
            return 1
        publisher.publish(UInt16(data=ord(options.key)))
        if not publisher.wait_for_all_acked(Duration(seconds=options.wait)):
            print(
                f"smacc-key: {options.topic}'s subscriber did not acknowledge {options.key!r} within "
                f"{options.wait:.0f} s; press it again (--wait sets the limit)",
                file=sys.stderr,
            )
            return 1
        print(f"smacc-key: sent {options.key!r} on {options.topic}")
        return 0

    # argv[0] only: the key and options are not rclpy's (a --ros-args tail was never accepted here).
    return run_nodes(build, role="smacc_key", rclpy_args=sys.argv[:1], finished=finished,
                     interrupted_code=130, lockstep=False)


if __name__ == "__main__":
    sys.exit(main())
