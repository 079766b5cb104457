"""``smacc-run <sm> [--ros-args ...]``: run a state machine on its own ROS node until Ctrl-C.

Example::

    smacc-run sm_nav2_test_1 --ros-args --params-file config/sm_nav2_test_1.yaml -p use_sim_time:=true

Each transition is logged on the node's logger as it happens.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")


def main(argv: Sequence[str] | None = None) -> int:
    import rclpy
    from rclpy.utilities import remove_ros_args

    from smacc_py.ros.loader import load_state_machine
    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.ros.transition_printer import TransitionPrinter

    args_in = list(sys.argv if argv is None else ["smacc-run", *argv])
    parser = argparse.ArgumentParser(prog="smacc-run", description=__doc__.splitlines()[0])
    parser.add_argument("state_machine", help="sm_nav2_test_1, a module path, or module:Class")
    options = parser.parse_args(remove_ros_args(args_in)[1:])
    try:
        sm_type = load_state_machine(options.state_machine)
    except ValueError as error:
        print(f"smacc-run: {error}", file=sys.stderr)
        return 2
    rclpy.init(args=args_in)
    runtime = None
    try:
        runtime = SmaccRuntime(sm_type)
        logger = runtime.node.get_logger()
        runtime.sm.add_observer(TransitionPrinter(lambda line: logger.info(line)))
        runtime.start()
        runtime.spin()
    except ValueError as error:  # bad parameters: the message names node, parameter and value
        print(f"smacc-run: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        pass
    finally:
        if runtime is not None:
            runtime.shutdown()
        if rclpy.ok():
            rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
