"""Waiting behaviors: CbWaitNav2Nodes (bond heartbeats), CbWaitPose and CbWaitTransform (TF),
CbSetInitialPose (AMCL).

Each one is a CbOutcomeBase: it polls on the machine clock (ISmaccUpdatable) for its timeout, so
timeouts follow sim time, and posts exactly one EvCbSuccess or EvCbFailure (payload ``reason`` on
failure).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ros_tools.tf import Transform, TransformError
from smacc_py.clients.cl_nav2z.client import ClNav2Z
from smacc_py.clients.cl_nav2z.cp_amcl import CpAmcl
from smacc_py.clients.cl_nav2z.cp_pose import CpPose
from smacc_py.clients.cl_nav2z.geometry import normalize_angle
from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import check_duration


class _Nav2Wait(CbOutcomeBase):
    """CbOutcomeBase with the strict timeout these waits always had (see ``strict_timeout``)."""

    strict_timeout = True


class CbWaitNav2Nodes(_Nav2Wait):
    """Success once each node in ``nodes`` heartbeated an active bond on ``topic``; failure after
    ``timeout_s`` (SMACC2's version never fails). Node ids are Nav2's bond ids (the node names). The
    subscription belongs to ClNav2Z (``subscribe_bonds``), which must be on the behavior's orthogonal."""

    DEFAULT_NODES = ("planner_server", "controller_server", "bt_navigator")

    def __init__(
        self, nodes: Sequence[str] = DEFAULT_NODES, topic: str = "bond", timeout_s: float | None = 30.0
    ) -> None:
        if not nodes:
            raise ValueError("CbWaitNav2Nodes: give at least one node id")
        self.nodes, self.topic, self.timeout_s = tuple(nodes), topic, timeout_s
        self.seen: set[str] = set()

    def start(self) -> None:
        # Sim time waits for the heartbeats themselves (they follow the wall clock), so Nav2 is up
        # at the same sim time on every run (see ClNav2Z.subscribe_bonds).
        self._unsubscribe = self.requires_client(ClNav2Z).subscribe_bonds(
            self._on_bond, self.topic, hold_until=lambda: self.finished)

    def _on_bond(self, node_id: str, active: bool) -> None:
        if active and node_id in self.nodes:
            self.seen.add(node_id)
            if self.seen.issuperset(self.nodes):
                self.finish(True, nodes=self.nodes)

    def timeout_reason(self) -> str:
        missing = ", ".join(n for n in self.nodes if n not in self.seen)
        return f"no active bond from {missing} within {self.timeout_s} s"

    def stop(self) -> None:
        self._unsubscribe()


class CbWaitPose(_Nav2Wait):
    """Success once CpPose finds the robot pose; failure after ``timeout_s``."""

    def __init__(self, timeout_s: float | None = 10.0) -> None:
        self.timeout_s = timeout_s

    def start(self) -> None:
        self._cp_pose = self.requires_component(CpPose)

    def poll(self) -> None:
        pose = self._cp_pose.refresh()
        if pose is not None:
            self.finish(True, pose=pose)

    def timeout_reason(self) -> str:
        return f"no robot pose within {self.timeout_s} s: {self._cp_pose.last_error}"


class CbWaitTransform(_Nav2Wait):
    """Success once TF has a transform between ``target_frame`` and ``reference_frame``; failure after
    ``timeout_s`` s of machine clock (the node clock: sim time under ``use_sim_time``).

    As SMACC2's, it looks up tf2's ``lookupTransform(target_frame, reference_frame)``: the success payload
    ``transform`` (a ros_tools.tf Transform) maps points in ``reference_frame`` into ``target_frame``.
    SMACC2's blocks its thread in tf2's wait; this one tries on entry and on every runtime poll.
    """

    def __init__(self, target_frame: str, reference_frame: str, timeout_s: float = 10.0) -> None:
        for field, frame in (("target_frame", target_frame), ("reference_frame", reference_frame)):
            if not isinstance(frame, str) or not frame.strip("/ "):
                raise ValueError(f"CbWaitTransform: {field} must name a frame, got {frame!r}")
        self.target_frame, self.reference_frame = target_frame.strip("/ "), reference_frame.strip("/ ")
        self.timeout_s = check_duration("CbWaitTransform", "timeout_s", timeout_s)
        self.result: Transform | None = None
        self.last_error = "not looked up yet"

    def start(self) -> None:
        self._client = self.requires_client(ClNav2Z)
        self.poll()

    def poll(self) -> None:
        try:
            self.result = self._client.lookup_transform(self.target_frame, self.reference_frame)
        except TransformError as error:
            self.last_error = str(error)
            return
        self.finish(True, transform=self.result)

    def timeout_reason(self) -> str:
        return (f"CbWaitTransform: no transform {self.target_frame} <- {self.reference_frame} within "
                f"{self.timeout_s} s: {self.last_error}")


class CbSetInitialPose(_Nav2Wait):
    """Publish AMCL's initial pose (x, y in m, yaw in rad, map frame) through CpAmcl, republishing every
    ``republish_period_s`` (machine clock), until AMCL's next estimate lies within ``xy_tolerance`` m
    and ``yaw_tolerance`` rad of it (success, payload ``amcl_pose``); failure after ``timeout_s``.

    Only estimates that arrive after the behavior starts count: AMCL's latched /amcl_pose from before
    says where it thought the robot was, not that it took this pose.
    """

    def __init__(
        self,
        x: float,
        y: float,
        yaw: float = 0.0,
        *,
        xy_tolerance: float = 0.5,
        yaw_tolerance: float = 0.5,
        timeout_s: float | None = 15.0,
        republish_period_s: float = 1.0,
    ) -> None:
        self.pose = (float(x), float(y), float(yaw))
        self.xy_tolerance, self.yaw_tolerance = xy_tolerance, yaw_tolerance
        self.timeout_s, self.republish_period_s = timeout_s, republish_period_s
        self.last_amcl: tuple[float, float, float] | None = None

    def start(self) -> None:
        self.requires_client(ClNav2Z)
        self._amcl = self.requires_component(CpAmcl)
        self._unlisten = self._amcl.listen(self._on_estimate)
        self._published_s = self.sm.now()
        self._amcl.set_initial_pose(*self.pose)

    def _on_estimate(self, estimate: tuple[float, float, float]) -> None:
        self.last_amcl = estimate
        x, y, yaw = self.pose
        if (
            math.hypot(estimate[0] - x, estimate[1] - y) <= self.xy_tolerance
            and abs(normalize_angle(estimate[2] - yaw)) <= self.yaw_tolerance
        ):
            self.finish(True, amcl_pose=estimate)

    def poll(self) -> None:
        if self.sm.now() - self._published_s >= self.republish_period_s:
            self._published_s = self.sm.now()
            self._amcl.set_initial_pose(*self.pose)

    def timeout_reason(self) -> str:
        return (
            f"AMCL did not report a pose near {self.pose} within {self.timeout_s} s "
            f"(last /amcl_pose: {self.last_amcl})"
        )

    def stop(self) -> None:
        self._unlisten()
