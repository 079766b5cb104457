"""Stand-ins for the cl_nav2z pieces added by issue 21 (item 2), on top of smacc_fake_nav's ScriptedNav2.

``MoreNav2`` is a ScriptedNav2 that also fakes, on the same manual machine clock:

* TF for CbWaitTransform: ``frames[(target, source)] = (transform, available_from_s)``; a lookup before
  that machine time, or of a pair not listed, raises TransformError with tf2's wording;
* the SLAM node's pause service (std_srvs/SetBool): ``slam_paused`` follows the requests it accepts;
  ``slam_up`` False hides the server, ``slam_refuses`` True answers success=False;
* the costmap nodes' SetParameters services: ``costmap_params[node][name]`` holds the declared
  parameters; setting an undeclared one is refused as rclpy refuses it.

Service requests are answered at the next poll (``sm.update()``), as a server on another thread
would answer some time after the request. The service-calling components get the manual clock as
their wall clock, so their deadlines are on the scripted timeline only.

The machines both test files run are built here too: ``OrNav`` (ClNav2Z with every cl_nav2z component
these tests need), ``chain`` (one behavior per state) and ``add_until_reached`` (the waypoint loop).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

from rcl_interfaces.msg import SetParametersResult
from rcl_interfaces.srv import SetParameters
from std_srvs.srv import SetBool

from ros_tools.tf import Transform, TransformError
from smacc_py.clients.cl_nav2z import (
    CbNavigateNextWaypointUntilReached,
    ClNav2Z,
    CpCostmapSwitch,
    CpPose,
    CpSlamToolbox,
    CpWaypointNavigator,
    CpWaypointsVisualizer,
    Waypoint,
)
from smacc_py.clients.cl_nav2z.service_caller import ServiceCaller
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvCbFailure,
    EvCbSuccess,
    EvGoalWaypointReached,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from tests.helpers.smacc_fake_nav import Nav2Script, RecordingPublisher, ScriptedNav2
from tests.helpers.smacc_stand_ins import ScriptedClNav2Z

__all__ = ["WAYPOINTS", "FakeServiceClient", "MoreNav2", "OrNav", "SmNav", "add_until_reached", "chain"]

WAYPOINTS = [Waypoint(1.0, 0.0, 0.0, "a"), Waypoint(2.0, 0.5, 1.0, "b"), Waypoint(2.0, 1.5, 0.0, "c")]

Handler = Callable[[Any], Any]


class FakeFuture:
    """The part of rclpy's Future that ServiceCall uses."""

    def __init__(self) -> None:
        self._result: Any = None
        self._done = False
        self._callbacks: list[Callable[[FakeFuture], None]] = []

    def done(self) -> bool:
        return self._done

    def result(self) -> Any:
        return self._result

    def add_done_callback(self, callback: Callable[[FakeFuture], None]) -> None:
        self._callbacks.append(callback)

    def set_result(self, result: Any) -> None:
        self._result, self._done = result, True
        for callback in self._callbacks:
            callback(self)


class FakeServiceClient:
    """Stands in for an rclpy service client; ``answer()`` serves the pending requests with ``handler``."""

    def __init__(self, srv_name: str, handler: Handler, ready: Callable[[], bool]) -> None:
        self.srv_name, self.handler, self.ready = srv_name, handler, ready
        self.requests: list[Any] = []
        self._pending: list[tuple[Any, FakeFuture]] = []

    def service_is_ready(self) -> bool:
        return self.ready()

    def call_async(self, request: Any) -> FakeFuture:
        future = FakeFuture()
        self.requests.append(request)
        self._pending.append((request, future))
        return future

    def remove_pending_request(self, future: FakeFuture) -> None:
        self._pending = [(r, f) for r, f in self._pending if f is not future]

    def answer(self) -> None:
        pending, self._pending = self._pending, []
        for request, future in pending:
            future.set_result(self.handler(request))


class _ScriptedServiceCaller(ServiceCaller):
    """The world's clock as wall clock; fake clients that answer on each poll."""

    world: MoreNav2
    fake_clients: list[FakeServiceClient]

    def wall_now(self) -> float:
        return self.world.clock()

    def make_client(self, srv_type: Any, service_name: str) -> FakeServiceClient:
        client = self.world.service_client(srv_type, service_name)
        self.fake_clients.append(client)
        return client

    def update(self) -> None:
        for client in self.fake_clients:
            client.answer()
        super().update()


class ScriptedCpSlamToolbox(_ScriptedServiceCaller, CpSlamToolbox):
    def __init__(self, world: MoreNav2, *args: Any, **kwargs: Any) -> None:
        CpSlamToolbox.__init__(self, *args, **kwargs)
        self.world, self.fake_clients = world, []


class ScriptedCpCostmapSwitch(_ScriptedServiceCaller, CpCostmapSwitch):
    def __init__(self, world: MoreNav2, *args: Any, **kwargs: Any) -> None:
        CpCostmapSwitch.__init__(self, *args, **kwargs)
        self.world, self.fake_clients = world, []


class ScriptedCpWaypointsVisualizer(CpWaypointsVisualizer):
    """Publishes into a RecordingPublisher."""

    def on_initialize(self) -> None:
        self._navigator = self.requires_component(CpWaypointNavigator)
        self._pub = RecordingPublisher()  # type: ignore[assignment]


class TfScriptedClNav2Z(ScriptedClNav2Z):
    """ScriptedClNav2Z whose TF lookups read ``MoreNav2.frames``."""

    world: MoreNav2

    def lookup_transform(self, target_frame: str, source_frame: str) -> Transform:
        transform, from_s = self.world.frames.get((target_frame, source_frame), (None, 0.0))
        if transform is None or self.world.clock() < from_s:
            raise TransformError(
                f'"{source_frame}" passed to lookupTransform argument source_frame does not exist'
            )
        return transform


class MoreNav2(ScriptedNav2):
    """ScriptedNav2 plus TF pairs, the SLAM pause service and the costmap parameter services."""

    def __init__(self, script: Nav2Script | None = None) -> None:
        super().__init__(script)
        self.frames: dict[tuple[str, str], tuple[Transform, float]] = {}
        self.slam_paused, self.slam_up, self.slam_refuses = False, True, False
        self.costmap_params: dict[str, dict[str, Any]] = {
            f"/{costmap}/{costmap}": {
                f"{layer}.enabled": True for layer in ("obstacle_layer", "inflation_layer")
            }
            for costmap in ("global_costmap", "local_costmap")
        }

    def substitutes(self) -> dict[type, Callable[..., object]]:
        return super().substitutes() | {
            ClNav2Z: functools.partial(TfScriptedClNav2Z, self),
            CpSlamToolbox: functools.partial(ScriptedCpSlamToolbox, self),
            CpCostmapSwitch: functools.partial(ScriptedCpCostmapSwitch, self),
            CpWaypointsVisualizer: ScriptedCpWaypointsVisualizer,
        }

    def service_client(self, srv_type: Any, service_name: str) -> FakeServiceClient:
        """A fake client of the SLAM node's pause service or of a costmap node's set_parameters."""
        if srv_type is SetBool:
            return FakeServiceClient(service_name, self._on_pause, lambda: self.slam_up)
        node = service_name.removesuffix("/set_parameters")
        return FakeServiceClient(
            service_name,
            functools.partial(self._on_set_parameters, node),
            lambda: node in self.costmap_params,
        )

    def _on_pause(self, request: SetBool.Request) -> SetBool.Response:
        if self.slam_refuses:
            return SetBool.Response(success=False, message="not now")
        self.slam_paused = request.data
        return SetBool.Response(success=True, message="paused" if request.data else "resumed")

    def _on_set_parameters(self, node: str, request: Any) -> Any:
        declared = self.costmap_params[node]
        results = []
        for parameter in request.parameters:
            if parameter.name in declared:
                declared[parameter.name] = parameter.value.bool_value
                results.append(SetParametersResult(successful=True))
            else:
                results.append(
                    SetParametersResult(
                        successful=False, reason=f"Parameter {parameter.name} is not declared"
                    )
                )
        return SetParameters.Response(results=results)


# ------------------------------------------------------------------ machines
class OrNav(Orthogonal):
    """ClNav2Z with CpPose (base_link in map), the WAYPOINTS navigator, its visualizer, CpSlamToolbox
    and CpCostmapSwitch (5 s timeouts)."""

    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpWaypointNavigator, WAYPOINTS)
        client.create_component(CpWaypointsVisualizer)
        client.create_component(CpSlamToolbox, timeout_s=5.0)
        client.create_component(CpCostmapSwitch, timeout_s=5.0)


class SmNav(SmaccStateMachineBase):
    """Base of the test machines: one orthogonal, OrNav."""

    def on_initialize(self) -> None:
        self.create_orthogonal(OrNav)


Step = tuple[type, tuple[Any, ...], dict[str, Any]]


def chain(name: str, steps: list[Step], last_target: str = "StDone") -> type[SmNav]:
    """A machine running ``steps`` (behavior, args, kwargs) in states St0, St1 ...: EvCbSuccess leads to the
    next state (from the last one to ``last_target``), EvCbFailure to StFailed. Declares StDone and
    StFailed; a ``last_target`` other than StDone is the caller's to declare."""
    sm = type(name, (SmNav,), {"initial_state": "St0" if steps else last_target})
    for i, (behavior, args, kwargs) in enumerate(steps):
        target = f"St{i + 1}" if i + 1 < len(steps) else last_target

        def configure(cls: type[SmaccState], behavior: type = behavior, args: tuple[Any, ...] = args,
                      kwargs: dict[str, Any] = kwargs) -> None:
            cls.configure_orthogonal(OrNav, behavior, *args, **kwargs)

        reactions = [Transition(EvCbSuccess[behavior, OrNav], target, SUCCESS),
                     Transition(EvCbFailure[behavior, OrNav], "StFailed", ABORT)]
        type(f"St{i}", (SmaccState,), {"reactions": reactions, "static_configure": classmethod(configure)},
             parent=sm)
    type("StDone", (SmaccState,), {}, parent=sm)
    type("StFailed", (SmaccState,), {}, parent=sm)
    return sm


def add_until_reached(sm: type[SmNav], name: str, goal_waypoint_name: str) -> type[SmaccState]:
    """State ``name`` of ``sm``: CbNavigateNextWaypointUntilReached(goal); each leg's EvCbSuccess re-enters
    it, EvGoalWaypointReached leads to StDone, EvCbFailure to StFailed."""
    cb = CbNavigateNextWaypointUntilReached
    reactions = [Transition(EvGoalWaypointReached[cb, OrNav], "StDone", SUCCESS),
                 Transition(EvCbSuccess[cb, OrNav], name, SUCCESS),
                 Transition(EvCbFailure[cb, OrNav], "StFailed", ABORT)]

    def configure(cls: type[SmaccState]) -> None:
        cls.configure_orthogonal(OrNav, cb, goal_waypoint_name)

    return type(name, (SmaccState,), {"reactions": reactions, "static_configure": classmethod(configure)},
                parent=sm)
