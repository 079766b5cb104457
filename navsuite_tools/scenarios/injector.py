"""Apply a scenario's events at their sim times: a small node that watches /clock and acts on the world.

Events (values as in the scenario file; navsuite_tools.scenarios.schema lists them):

* the sim2d requests (``kidnap``, ``lidar_dropout``, ``obstacle``, ``obstacle_on_path``, ``topic_loss``,
  ``odom_slip``, ``clock_pause``): one message or service call each, navsuite_tools.scenarios.sim_events;
* ``kill_<process>``: SIGKILL, ``freeze_<process>``: SIGSTOP then SIGCONT after the event's wall
  seconds, of the navigation or localization process (the lockstep participant whose pid it read on
  /lockstep/progress) or of the simulator (found in the process table), always a process of this
  scenario (navsuite_tools.scenarios.process_faults: which process, and the guard). The injector does it,
  not the worker, because only the injector follows sim time. nav-bringup then respawns a killed node
  process (its ``use_respawn``; with ``--no-respawn`` the launch ends and the mission with STACK); a
  killed simulator ends the launch at once, naming it.

It is a lockstep participant (role ``scenario_events``) that reports only once every channel it needs
is ready (every publisher matched by the simulator's subscription, the pause service found, the pid of
every process it targets heard); the farm also names the role in nav-bringup's ``--participant``
list, so the simulator does not step before the injector is there and never runs more than one
lockstep lead (0.05 s) past an event's time. An event waits while its channel is not ready, so none
is lost. It stays up after its last event until the worker stops it: a process that exits right
after publishing may take the message (and its lockstep leave) down with it, and the simulator would
then wait 5 s wall for the silent participant. A process it froze is continued before it exits.

Each applied event is printed as ``applied <kind> <what> at t=<sim s>`` (the worker keeps these lines
for the run report's ``events_applied``); one that cannot be applied as ``injector: <kind> at t=...
not applied: <why>``.

Usage: ``python -m navsuite_tools.scenarios.injector '<json list of {"at": s, "<kind>": value}>'``.
"""

from __future__ import annotations

import json
import os
import signal
import sys
from collections.abc import Sequence
from typing import Any

from navsuite_tools.scenarios.process_faults import (
    FreezeBook,
    process_exists,
    role_pid,
    send,
    simulator_pid,
    target_of,
)
from navsuite_tools.scenarios.sim_events import SIM_EVENTS, Applier, sim_applier

ROLE = "scenario_events"
PROCESS_EVENTS = tuple(f"{action}_{target}" for action in ("kill", "freeze")
                       for target in ("navigation", "localization", "simulator"))
KINDS = (*SIM_EVENTS, *PROCESS_EVENTS)


def build_node(events: list[dict[str, Any]], book: FreezeBook | None = None) -> Any:
    """The injector node; ``events`` are applied in order of ``at`` (s of sim time); ``book`` keeps the
    processes it froze (for the caller to continue at exit)."""
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rosgraph_msgs.msg import Clock

    from ros_tools.runtime.waiting import steady_clock

    node = Node("scenario_events")
    reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    pending = sorted(events, key=lambda event: float(event["at"]))
    kinds = {_kind(event) for event in pending}
    appliers: dict[str, Applier] = {}
    pids = _ProcessTargets(node, {target_of(kind) for kind in kinds if kind in PROCESS_EVENTS})
    book = book if book is not None else FreezeBook()
    for kind in kinds:
        if kind in SIM_EVENTS:
            appliers[kind] = sim_applier(node, kind, reliable, steady_clock())
        else:
            appliers[kind] = _process_applier(node, kind, pids, book, steady_clock())

    def on_clock(msg: Clock) -> None:
        now = msg.clock.sec + msg.clock.nanosec * 1e-9
        while pending and now >= float(pending[0]["at"]):
            kind = _kind(pending[0])
            ready, apply = appliers[kind]
            if not ready():
                return
            event = pending.pop(0)
            try:
                what = apply(event[kind], msg.clock)
            except (OSError, ValueError) as error:  # the process is gone, not ours, or no place: say so
                print(f"injector: {kind} at t={now:.2f} s not applied: {error}", flush=True)
                continue
            print(f"applied {kind} {what} at t={now:.2f} s", flush=True)

    node.create_subscription(Clock, "/clock", on_clock, reliable)
    # Every channel, the pids included: an injector that joined before it had heard the navigation
    # pid let the simulator run past a kill's time (CI run CN: "at t=5.0" applied at 6.80 s).
    channels_ready = [ready for ready, _ in appliers.values()]
    node.scenario_ready = lambda: all(ready() for ready in channels_ready)  # type: ignore[attr-defined]
    return node


class _ProcessTargets:
    """The pids of the processes the events target: participants from /lockstep/progress (the first
    live pid heard, replaced once that process is gone: a respawn), the simulator from /proc."""

    def __init__(self, node: Any, targets: set[str]) -> None:
        from std_msgs.msg import Header

        from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC

        self.ancestor = os.getppid()  # the worker: every target descends from it
        self._pids: dict[str, int] = {}
        self._targets = targets
        if targets - {"simulator"}:
            node.create_subscription(Header, PROGRESS_TOPIC, self._heard, PROGRESS_QOS)

    def _heard(self, msg: Any) -> None:
        for target in self._targets - {"simulator"}:
            pid = role_pid(target, msg.frame_id)
            if pid is not None and (target not in self._pids or not process_exists(self._pids[target])):
                self._pids[target] = pid

    def pid(self, target: str) -> int | None:
        if target == "simulator" and target not in self._pids:
            found = simulator_pid(self.ancestor)
            if found is not None:
                self._pids[target] = found
        return self._pids.get(target)


def _process_applier(node: Any, kind: str, pids: _ProcessTargets, book: FreezeBook, steady: Any) -> Applier:
    """(ready, apply) of kill_<process> / freeze_<process>: ready once the target's pid is known."""
    target = target_of(kind)

    def apply(value: Any, _stamp: Any) -> str:
        pid = pids.pid(target)
        assert pid is not None  # ready() said so
        if kind.startswith("kill_"):
            send(pid, signal.SIGKILL, pids.ancestor)
            return f"pid {pid}"
        seconds = float(value)
        book.freeze(pid, pids.ancestor)

        def thaw() -> None:
            node.destroy_timer(timer)
            state = "continued" if book.thaw(pid) else "gone before its SIGCONT"
            print(f"injector: {target} (pid {pid}) {state} after {seconds:g} s wall", flush=True)

        timer = node.create_timer(seconds, thaw, clock=steady)
        return f"pid {pid} for {seconds:g} s wall"

    return (lambda: pids.pid(target) is not None), apply


def _kind(event: dict[str, Any]) -> str:
    return next(key for key in event if key != "at")


def main(argv: Sequence[str] | None = None) -> int:
    from ros_tools.runtime.runner import run_nodes

    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    events = json.loads(args[0])
    unsupported = [event for event in events if not isinstance(event, dict) or len(event) != 2
                   or "at" not in event or _kind(event) not in KINDS]
    if unsupported:
        print(f"injector: unsupported events {unsupported} (kinds: {', '.join(KINDS)})", file=sys.stderr)
        return 2
    nodes: list[Any] = []
    book = FreezeBook()

    def build() -> list[Any]:
        nodes.append(build_node(events, book))
        return nodes

    try:
        return run_nodes(build, role=ROLE, rclpy_args=["--ros-args", "-p", "use_sim_time:=true"],
                         ready=lambda: bool(nodes) and nodes[0].scenario_ready())
    finally:
        book.thaw_all()  # never leave a process of the run stopped


if __name__ == "__main__":
    sys.exit(main())
