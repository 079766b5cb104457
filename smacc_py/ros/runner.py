"""``smacc-run <sm> [--ros-args ...]``: run a state machine on its own ROS node until Ctrl-C.

Examples::

    smacc-run sm_nav2_test_1 --ros-args --params-file config/sm_nav2_test_1.yaml -p use_sim_time:=true
    smacc-run my_pkg.sm_foo            # a module path (sys.path or the current directory)
    smacc-run ./sm_my_machine          # a package folder, e.g. one written by smacc-new
    smacc-run ./sm_foo.py:SmFoo        # a module file, naming the class

``smacc_py.ros.loader`` resolves the name (a name found nowhere lists every place looked, exit 2).
Each transition is logged on the node's logger as it happens. ``--executor single`` runs the node on
rclpy's SingleThreadedExecutor instead of the C++ EventsExecutor (default: ``$NAVSUITE_EXECUTOR`` or
``events``). Ctrl-C or SIGTERM ends the run quietly with exit status 0: the signal only sets a flag
that the spin loop checks between two executor turns (an exception raised from a signal handler
would surface inside whichever callback the executor was running, as a logged traceback), then the
machine stops while the node can still talk (behaviors' on_exit cancel their goals and zero the
velocity) and everything is torn down. rclpy's own signal handler, which would shut the context down
first, is off; signals during the teardown are ignored.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ros_tools.runtime.runner import StopOnSignal, ros_process


def main(argv: Sequence[str] | None = None) -> int:
    # First: a Ctrl-C while rclpy and the machine import must not print a traceback. The same flag
    # serves the whole run (ros_process is told not to install its own) and, once there is a runtime,
    # also asks it to stop.
    stop = StopOnSignal()
    try:
        return _run(argv, stop)
    finally:
        stop.restore()


def _run(argv: Sequence[str] | None, stop: StopOnSignal) -> int:
    from rclpy.utilities import remove_ros_args

    from ros_tools.runtime.executor import add_executor_argument
    from smacc_py.core import SmaccError
    from smacc_py.ros.loader import load_state_machine
    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.ros.transition_printer import TransitionPrinter

    args_in = list(sys.argv if argv is None else ["smacc-run", *argv])
    parser = argparse.ArgumentParser(prog="smacc-run", description=__doc__.splitlines()[0])
    parser.add_argument("state_machine", help="sm_nav2_test_1, a module path, a .py file or package folder, "
                                              "optionally followed by :ClassName")
    add_executor_argument(parser)
    options = parser.parse_args(remove_ros_args(args_in)[1:])
    try:
        sm_type = load_state_machine(options.state_machine)
    except ValueError as error:  # not found, or a definition error while importing the machine
        print(f"smacc-run: {error}", file=sys.stderr)
        return 2
    if stop.requested:
        return 0
    # The runtime owns its executor and spin loop (smacc_py.ros.runtime), so this is the runner's
    # process shape without its spin loop: rclpy's signal handler off, the context shut down last.
    with ros_process(args_in, handle_signals=False):
        runtime = None
        try:
            runtime = SmaccRuntime(sm_type, executor=options.executor)
            stop.on_stop = runtime.request_stop
            if stop.requested:
                return 0
            logger = runtime.node.get_logger()
            runtime.sm.add_observer(TransitionPrinter(lambda line: logger.info(line)))
            runtime.start()
            runtime.spin()
        except (ValueError, SmaccError) as error:  # bad parameters or configuration: the message names them
            print(f"smacc-run: {error}", file=sys.stderr)
            return 2
        finally:
            if runtime is not None:
                runtime.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
