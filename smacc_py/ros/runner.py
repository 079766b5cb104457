"""``smacc-run <sm> [--ros-args ...]``: run a state machine on its own ROS node until Ctrl-C.

Example::

    smacc-run sm_nav2_test_1 --ros-args --params-file config/sm_nav2_test_1.yaml -p use_sim_time:=true

Each transition is logged on the node's logger as it happens. ``--executor single`` runs the node on
rclpy's SingleThreadedExecutor instead of the C++ EventsExecutor (default: ``$NAVSUITE_EXECUTOR`` or
``events``). Ctrl-C or SIGTERM stops the machine while the node can still talk (behaviors' on_exit
cancel their goals and zero the velocity), then tears everything down: rclpy's own signal handler,
which would shut the context down first, is off.
"""

from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Sequence
from types import FrameType

from ros_tools.dds import keep_dds_local

keep_dds_local()


def _interrupt(signum: int, frame: FrameType | None) -> None:
    """SIGINT and SIGTERM raise KeyboardInterrupt: spinning ends, then the runtime shuts down. Set
    explicitly, as a process started in the background by a shell inherits SIGINT ignored."""
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    from rclpy.utilities import remove_ros_args

    from ros_tools.runtime.executor import add_executor_argument
    from smacc_py.ros.loader import load_state_machine
    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.ros.transition_printer import TransitionPrinter

    args_in = list(sys.argv if argv is None else ["smacc-run", *argv])
    parser = argparse.ArgumentParser(prog="smacc-run", description=__doc__.splitlines()[0])
    parser.add_argument("state_machine", help="sm_nav2_test_1, a module path, or module:Class")
    add_executor_argument(parser)
    options = parser.parse_args(remove_ros_args(args_in)[1:])
    try:
        sm_type = load_state_machine(options.state_machine)
    except ValueError as error:
        print(f"smacc-run: {error}", file=sys.stderr)
        return 2
    rclpy.init(args=args_in, signal_handler_options=SignalHandlerOptions.NO)
    previous = {sig: signal.signal(sig, _interrupt) for sig in (signal.SIGINT, signal.SIGTERM)}
    runtime = None
    try:
        runtime = SmaccRuntime(sm_type, executor=options.executor)
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
        try:
            if runtime is not None:
                runtime.shutdown()
        finally:
            for sig, handler in previous.items():
                signal.signal(sig, handler)
            if rclpy.ok():
                rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
