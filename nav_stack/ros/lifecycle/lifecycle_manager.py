"""Lifecycle managers (lifecycle_manager_localization / _navigation), as nav2_lifecycle_manager.

Why: Nav2 brings its servers up in a fixed order (configure all, then activate all) and watches
each one's bond heartbeat; clients such as BasicNavigator and SMACC2's CbWaitNav2Nodes rely on the
``<manager>/manage_nodes`` and ``<manager>/is_active`` services and on that behaviour.

A plain rclpy node (not itself a lifecycle node). Parameters (Nav2 Jazzy names): ``node_names``,
``autostart`` (False), ``bond_timeout`` (4.0 s; 0 disables bonds), ``attempt_respawn_reconnection``
(True) and ``bond_respawn_max_duration`` (10.0 s); ``service_timeout`` (s, ours) bounds every wait
for a managed node's service.

Commands (nav2_msgs/srv/ManageLifecycleNodes): STARTUP configures every node in order, then
activates every node in order and waits for its bond; PAUSE deactivates in reverse order; RESUME
activates in order; RESET deactivates and cleans up in reverse order; SHUTDOWN resets, then shuts
every node down; CONFIGURE / CLEANUP apply only that transition. A node already in a transition's
goal state is skipped. "Managed nodes are active" is logged when a startup or resume completes.

Bonds: active nodes heartbeat bond/msg/Status on ``bond`` with ``id`` = node name; the topic is
relative on both sides, as Nav2's, so the manager hears the nodes of its own namespace. When a heartbeat is
missing for ``bond_timeout`` (or the node reports its bond inactive while the system is active),
the manager logs Nav2's CRITICAL FAILURE message, resets every other node, and (with
``attempt_respawn_reconnection``) re-runs startup once all nodes answer again, for up to
``bond_respawn_max_duration``: a respawned node process (nav-bringup's ``use_respawn``) answers
unconfigured; a frozen one (SIGSTOP past ``bond_timeout``) answers again on SIGCONT in whatever state
the reset could not change while it was frozen, and is reset again before the startup.

A manager that itself did not run for a while (its bond check came more than ``MANAGER_STALL`` late:
the process was starved of CPU, or another node of the same process held its thread) does not blame
the nodes for the heartbeats it has not read yet: silence is then counted from the moment it resumed,
so a loaded machine does not take a live stack down (Nav2 would; it has no such grace).

Nothing blocks the executor: every service call is awaited inside a coroutine callback, and the
waits use one-shot timers (steady clock: they are safety nets); commands run one at a time.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from bond.msg import Status
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState
from nav2_msgs.srv import ManageLifecycleNodes
from rclpy.client import Client
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.timer import Timer
from std_srvs.srv import Trigger

from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.lifecycle.node import BOND_QOS, BOND_TOPIC
from ros_tools.runtime.coroutines import create_async_service, in_task, spawn
from ros_tools.runtime.executor import reentrant_default_group
from ros_tools.runtime.requests import SERVICE_RETRY_S, call_service
from ros_tools.runtime.waiting import Serializer, sleep

BOND_CHECK_PERIOD = 0.2  # s, Nav2's bond timer
#: s between two bond checks beyond which the manager counts itself stalled (5 check periods)
MANAGER_STALL = 1.0
RESPAWN_CHECK_PERIOD = 1.0  # s
SERVICE_POLL_PERIOD = 0.1  # s
#: s before a change_state request is sent again: longer than a transition takes (a costmap's
#: configure on a large map), so that a normal bring-up sends each transition once.
TRANSITION_RESEND_S = 5.0
QUICK_TIMEOUT = 2.0  # s per call while tearing down after a bond failure (a dead node must not stall it)

GOAL_STATE = {
    Transition.TRANSITION_CONFIGURE: State.PRIMARY_STATE_INACTIVE,
    Transition.TRANSITION_CLEANUP: State.PRIMARY_STATE_UNCONFIGURED,
    Transition.TRANSITION_ACTIVATE: State.PRIMARY_STATE_ACTIVE,
    Transition.TRANSITION_DEACTIVATE: State.PRIMARY_STATE_INACTIVE,
    Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: State.PRIMARY_STATE_FINALIZED,
}
LABEL = {
    Transition.TRANSITION_CONFIGURE: "Configuring",
    Transition.TRANSITION_CLEANUP: "Cleaning up",
    Transition.TRANSITION_ACTIVATE: "Activating",
    Transition.TRANSITION_DEACTIVATE: "Deactivating",
    Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: "Shutting down",
}
FORWARD = (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE)


@dataclass(frozen=True)
class LifecycleManagerParams:
    """nav2_lifecycle_manager parameters (Jazzy names and defaults) plus ``service_timeout``."""

    node_names: tuple[str, ...] = ()
    autostart: bool = False
    bond_timeout: float = 4.0
    attempt_respawn_reconnection: bool = True
    bond_respawn_max_duration: float = 10.0
    service_timeout: float = 30.0

    def __post_init__(self) -> None:
        if len(set(self.node_names)) != len(self.node_names):
            raise ValueError(f"node_names lists a node twice: {list(self.node_names)}")
        if self.service_timeout <= 0.0:
            raise ValueError(f"service_timeout must be > 0 s, got {self.service_timeout}")


class LifecycleManager(Node):
    """Brings a list of lifecycle nodes up and down and watches their bonds."""

    def __init__(self, node_name: str = "lifecycle_manager", defaults: dict[str, Any] | None = None,
                 **kwargs: Any) -> None:
        """``defaults`` replace LifecycleManagerParams defaults (not values a parameter file sets):
        nav-bringup passes the node list and autostart, as Nav2's launch files do."""
        super().__init__(node_name, **kwargs)
        reentrant_default_group(self)
        self.params = declare_dataclass(self, LifecycleManagerParams, **(defaults or {}))
        self.step = "starting" if self.params.autostart else (  # what it does or awaits now
            f"a STARTUP request on {self.get_name()}/manage_nodes (autostart is false)")
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._commands = Serializer()  # one command (or bond recovery) at a time
        self.system_active = False
        self.bringup_failed = False  # the last startup aborted (a node failed to configure or activate)
        self._heartbeats: dict[str, float] = {}  # node → steady time of its last active heartbeat
        self._last_bond_check = self._steady_now()  # steady s
        self._silence_counted_from = self._last_bond_check  # steady s: after the manager's last stall
        self._bonded: set[str] = set()
        self._broken: set[str] = set()
        self._get_state: dict[str, Client] = {}
        self._change_state: dict[str, Client] = {}
        for name in self.params.node_names:
            self._get_state[name] = self.create_client(GetState, f"{name}/get_state")
            self._change_state[name] = self.create_client(ChangeState, f"{name}/change_state")
        create_async_service(self, ManageLifecycleNodes, f"{self.get_name()}/manage_nodes", self._on_manage)
        self.create_service(Trigger, f"{self.get_name()}/is_active", self._on_is_active)
        self._bond_sub = self.create_subscription(Status, BOND_TOPIC, self._on_bond, BOND_QOS)
        self.create_timer(BOND_CHECK_PERIOD, in_task(self, self._check_bonds), clock=self._steady)
        self._respawn_timer: Timer | None = None
        self._respawn_deadline = 0.0
        self._autostart_timer: Timer | None = None
        if self.params.autostart:
            self._autostart_timer = self.create_timer(0.0, self._autostart, clock=self._steady)

    # -- services --------------------------------------------------------------------------------
    async def _on_manage(self, request: ManageLifecycleNodes.Request,
                         response: ManageLifecycleNodes.Response) -> ManageLifecycleNodes.Response:
        commands: dict[int, Any] = {
            ManageLifecycleNodes.Request.STARTUP: self.startup,
            ManageLifecycleNodes.Request.PAUSE: self.pause,
            ManageLifecycleNodes.Request.RESUME: self.resume,
            ManageLifecycleNodes.Request.RESET: self.reset,
            ManageLifecycleNodes.Request.SHUTDOWN: self.shutdown,
            ManageLifecycleNodes.Request.CONFIGURE: lambda: self._all(Transition.TRANSITION_CONFIGURE),
            ManageLifecycleNodes.Request.CLEANUP: lambda: self._all(Transition.TRANSITION_CLEANUP),
        }
        command = commands.get(request.command)
        if command is None:
            self.get_logger().error(f"manage_nodes: unknown command {request.command}")
            response.success = False
        else:
            response.success = bool(await self._commands.run(command))
        return response

    def _on_is_active(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        response.success = self.system_active
        return response

    # -- commands --------------------------------------------------------------------------------
    def _message(self, text: str) -> None:
        self.get_logger().info(text)

    async def startup(self) -> bool:
        self._message("Starting managed nodes bringup...")
        if not (await self._all(Transition.TRANSITION_CONFIGURE)
                and await self._all(Transition.TRANSITION_ACTIVATE)):
            self.get_logger().error("Failed to bring up all requested nodes. Aborting bringup.")
            self.bringup_failed, self.step = True, "bringup aborted"
            return False
        self._message("Managed nodes are active")
        self.system_active, self.bringup_failed, self.step = True, False, "active"
        return True

    async def pause(self) -> bool:
        self.system_active = False
        self._message("Pausing managed nodes...")
        if not await self._all(Transition.TRANSITION_DEACTIVATE):
            self.get_logger().error("Failed to pause nodes: aborting pause")
            return False
        self._message("Managed nodes have been paused")
        return True

    async def resume(self) -> bool:
        self._message("Resuming managed nodes...")
        if not await self._all(Transition.TRANSITION_ACTIVATE):
            self.get_logger().error("Failed to resume nodes: aborting resume")
            return False
        self._message("Managed nodes are active")
        self.system_active = True
        return True

    async def reset(self, hard: bool = False) -> bool:
        """Deactivate and clean up in reverse order; ``hard`` carries on past failures (bond loss)."""
        self.system_active = False
        self._message("Resetting managed nodes...")
        ok = await self._all(Transition.TRANSITION_DEACTIVATE, hard)
        ok = (ok or hard) and await self._all(Transition.TRANSITION_CLEANUP, hard)
        if not ok and not hard:
            self.get_logger().error("Failed to reset nodes: aborting reset")
            return False
        self._message("Managed nodes have been reset")
        return True

    async def shutdown(self) -> bool:
        self.system_active = False
        self._stop_respawn()
        self._message("Shutting down managed nodes...")
        await self.reset(hard=True)
        await self._all(Transition.TRANSITION_UNCONFIGURED_SHUTDOWN, hard=True)
        self._message("Managed nodes have been shut down")
        return True

    async def _all(self, transition: int, hard: bool = False) -> bool:
        names = list(self.params.node_names)
        ok = True
        for name in names if transition in FORWARD else reversed(names):
            if not await self._change(name, transition, quick=hard):
                ok = False
                if not hard:
                    return False
        return ok

    # -- one node --------------------------------------------------------------------------------
    async def _call(self, client: Client, request: Any, quick: bool = False,
                    resend_after: float = SERVICE_RETRY_S) -> Any:
        """The response of one service call, or None when the service is missing or too slow.

        Waits up to ``service_timeout`` for the service and the answer; ``quick`` does not wait for a
        missing service and gives the answer QUICK_TIMEOUT. An unanswered request is sent again
        (ros_tools.runtime.requests: a response can be lost in discovery), so a transition may reach
        the node twice; :meth:`_change` judges by the node's state, not by one answer.
        """
        timeout = min(QUICK_TIMEOUT, self.params.service_timeout) if quick else self.params.service_timeout
        deadline = time.monotonic() + timeout
        polls = 0
        while not client.service_is_ready():
            if quick or time.monotonic() > deadline:
                self.get_logger().error(f"service {client.srv_name} is not available"
                                        + ("" if quick else f" after {timeout:.1f} s"))
                return None
            if polls % 20 == 19:
                self.get_logger().info(f"Waiting for service {client.srv_name}...")
            self.step = f"waiting for the service {client.srv_name}"
            polls += 1
            await sleep(self, SERVICE_POLL_PERIOD, self._steady)
        response = await call_service(self, client, request, max(0.1, deadline - time.monotonic()),
                                      self._steady, resend_after)
        if response is None:
            self.get_logger().error(f"service {client.srv_name} did not answer within {timeout:.1f} s")
        return response

    async def _state_of(self, name: str, quick: bool = False) -> int | None:
        response = await self._call(self._get_state[name], GetState.Request(), quick)
        return None if response is None else int(response.current_state.id)

    async def _change(self, name: str, transition: int, quick: bool = False) -> bool:
        goal = GOAL_STATE[transition]
        if transition == Transition.TRANSITION_DEACTIVATE:
            self._drop_bond(name)
        current = await self._state_of(name, quick)
        if current == goal:
            return await self._bond(name) if transition == Transition.TRANSITION_ACTIVATE else True
        self._message(f"{LABEL[transition]} {name}")
        self.step = f"{LABEL[transition].lower()} {name}"
        request = ChangeState.Request()
        request.transition.id = transition
        response = None if current is None else await self._call(self._change_state[name], request, quick,
                                                                 TRANSITION_RESEND_S)
        # The state decides: a resent copy of a transition that succeeded is answered "invalid".
        if response is None or await self._state_of(name, quick) != goal:
            self.get_logger().error(f"Failed to change state for node: {name}")
            return False
        return await self._bond(name) if transition == Transition.TRANSITION_ACTIVATE else True

    # -- bonds -----------------------------------------------------------------------------------
    def _on_bond(self, msg: Status) -> None:
        if msg.id not in self._get_state:
            return
        if msg.active:
            self._heartbeats[msg.id] = self._steady_now()
        elif msg.id in self._bonded:
            self._broken.add(msg.id)

    def _drop_bond(self, name: str) -> None:
        self._bonded.discard(name)
        self._broken.discard(name)

    async def _bond(self, name: str) -> bool:
        """Wait (bond_timeout / 2, as Nav2) for a heartbeat of the freshly activated node."""
        timeout = self.params.bond_timeout
        if timeout <= 0.0 or name in self._bonded:
            return True
        since = self._steady_now()
        deadline = time.monotonic() + timeout / 2.0
        self.step = f"waiting for {name}'s bond heartbeat on {self._bond_sub.topic_name}"
        while self._heartbeats.get(name, -1.0) < since - BOND_CHECK_PERIOD:
            if time.monotonic() > deadline:
                self.get_logger().error(f"Server {name} was unable to be reached after {timeout:.2f}s "
                                        "by bond. This server may be misconfigured.")
                return False
            await sleep(self, 0.05, self._steady)
        self._bonded.add(name)
        self._broken.discard(name)
        self.get_logger().info(f"Server {name} connected with bond.")
        return True

    def _steady_now(self) -> float:
        return self._steady.now().nanoseconds * 1e-9

    async def _check_bonds(self) -> None:
        now = self._steady_now()
        if now - self._last_bond_check > MANAGER_STALL:
            # this manager was stalled: heartbeats sent meanwhile may still wait unread in its queue
            self._silence_counted_from = now
        self._last_bond_check = now
        if not self.system_active or self.params.bond_timeout <= 0.0 or self._commands.busy:
            return
        await self._commands.run(self._recover_lost_bonds)

    async def _recover_lost_bonds(self) -> None:
        now = self._steady_now()
        for name in self.params.node_names:
            last_heard = max(self._heartbeats.get(name, now), self._silence_counted_from)
            silent = now - last_heard > self.params.bond_timeout
            if name in self._bonded and (silent or name in self._broken):
                self._message(f"Have not received a heartbeat from {name}.")
                self.get_logger().error(
                    f"CRITICAL FAILURE: SERVER {name} IS DOWN after not receiving a heartbeat for "
                    f"{int(self.params.bond_timeout * 1000)} ms. Shutting down related nodes.")
                self._drop_bond(name)
                await self.reset(hard=True)
                if self.params.attempt_respawn_reconnection:
                    self._start_respawn()
                return

    def _start_respawn(self) -> None:
        self._stop_respawn()
        self._respawn_deadline = time.monotonic() + self.params.bond_respawn_max_duration
        self._respawn_timer = self.create_timer(RESPAWN_CHECK_PERIOD, in_task(self, self._check_respawn),
                                                clock=self._steady)

    def _stop_respawn(self) -> None:
        if self._respawn_timer is not None:
            self.destroy_timer(self._respawn_timer)
            self._respawn_timer = None

    async def _check_respawn(self) -> None:
        if not self._commands.busy:
            await self._commands.run(self._try_respawn)

    async def _try_respawn(self) -> None:
        if self._respawn_timer is None:
            return
        if time.monotonic() > self._respawn_deadline:
            self.get_logger().error(
                f"Failed to bring up all requested nodes within {self.params.bond_respawn_max_duration:.1f} "
                "s; not retrying. Use manage_nodes STARTUP once they are back.")
            self._stop_respawn()
            return
        states = [await self._state_of(name, quick=True) for name in self.params.node_names]
        if all(state is not None for state in states):
            self._message("All managed nodes answer again: restarting them")
            self._stop_respawn()
            if any(state != State.PRIMARY_STATE_UNCONFIGURED for state in states):
                # A frozen node (SIGSTOP) missed the reset: it comes back in the state it froze in.
                self._message("A managed node missed the reset while it did not answer: resetting again")
                await self.reset(hard=True)
            if not await self.startup():
                self._start_respawn()

    def _autostart(self) -> None:
        """Once, as soon as the executor spins: start up the managed nodes."""
        if self._autostart_timer is not None:
            self.destroy_timer(self._autostart_timer)
            self._autostart_timer = None
            spawn(self, self._commands.run(self.startup))


def main(argv: list[str] | None = None) -> int:
    """Run one manager: ``--ros-args -r __node:=lifecycle_manager_localization --params-file ...``."""
    return run_nodes(lambda: [LifecycleManager()], argv, role="lifecycle_manager")


if __name__ == "__main__":
    raise SystemExit(main())
