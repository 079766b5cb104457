"""Run servers (and the costmap nodes they own) in one process: the ``main()`` of each server module.

Servers block one executor thread per running action goal, so they are spun by a
MultiThreadedExecutor with enough threads for every action plus timers and subscriptions. Nodes that
never block in a callback (map_server, amcl, the lifecycle managers) ask for a SingleThreadedExecutor:
it wakes for each message without handing work to a thread pool, which measurably keeps amcl up
with a simulator running at 4x real time where the thread pool did not.
``--autostart`` configures and activates the nodes (normally a lifecycle manager does it).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence

EXECUTOR_THREADS = 12


def run(build_nodes: Callable[[], Sequence[object]], argv: Sequence[str] | None = None,
        multithreaded: bool = True) -> int:
    """Build the nodes, optionally bring them up, spin until Ctrl-C; the exit code."""
    import rclpy
    from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor, SingleThreadedExecutor
    from rclpy.lifecycle import LifecycleNode

    import nav_stack.ros  # noqa: F401 - sets the LOCALHOST discovery default
    from ros_tools.shared_clock import share_sim_time

    args = list(sys.argv if argv is None else argv)
    autostart = "--autostart" in args
    rclpy.init(args=[a for a in args if a != "--autostart"])
    nodes: Sequence[object] = []
    try:
        nodes = build_nodes()
        share_sim_time(nodes)
        executor = (MultiThreadedExecutor(num_threads=EXECUTOR_THREADS) if multithreaded
                    else SingleThreadedExecutor())
        for node in nodes:
            executor.add_node(node)  # type: ignore[arg-type]
        if autostart:
            server = nodes[0]
            assert isinstance(server, LifecycleNode)
            server.trigger_configure()
            server.trigger_activate()
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        for node in nodes:
            node.destroy_node()  # type: ignore[attr-defined]
        if rclpy.ok():
            rclpy.shutdown()
    return 0
