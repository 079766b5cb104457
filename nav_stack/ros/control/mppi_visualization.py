"""What Nav2 Jazzy's mppi::TrajectoryVisualizer publishes for an MPPI controller with ``visualize``.

Why its own module: the sampled trajectories are thousands of spheres a cycle, so they are written
straight to CDR bytes (:class:`SphereArrayEncoder`) rather than built as Marker objects; that is a
concern of its own, apart from building the controller plugins.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.serialization import serialize_message
from visualization_msgs.msg import Marker, MarkerArray

from nav_stack.core.control import MPPIController
from nav_stack.core.control.mppi.visualization import trajectory_markers
from nav_stack.core.control.rotation_shim import RotationShim
from nav_stack.core.control.server import LocalController
from nav_stack.ros.common.conversions import path_from_array

#: Jazzy's TrajectoryVisualizer publishers: depth 1, reliable, volatile
VISUALIZATION_QOS = QoSProfile(depth=1)


class MPPIVisualization:
    """What Nav2 Jazzy's mppi::TrajectoryVisualizer publishes for MPPI controllers with ``visualize``:
    the sampled trajectories, thinned by ``TrajectoryVisualizer.trajectory_step`` / ``time_step``,
    and the optimal one as sphere markers on ``/trajectories`` (visualization_msgs/MarkerArray), and
    the path the critics saw on ``transformed_global_plan`` (nav_msgs/Path). Each only while someone
    subscribes. The markers go out serialized by :class:`SphereArrayEncoder`: 7656 Marker objects a
    cycle (Jazzy's defaults) took 370 ms to build in Python."""

    def __init__(self, node: Node, controllers: Mapping[str, LocalController]) -> None:
        self.node = node
        self.enabled = any(isinstance(c, MPPIController) and c.params.visualize
                           for c in map(_mppi_of, controllers.values()))
        self._encoders: dict[str, SphereArrayEncoder] = {}
        if self.enabled:
            self.markers = node.create_publisher(MarkerArray, "/trajectories", VISUALIZATION_QOS)
            self.plan = node.create_publisher(Path, "transformed_global_plan", VISUALIZATION_QOS)

    def publish(self, controller: LocalController, frame: str, stamp: Any) -> None:
        """After a cycle of ``controller`` (the running plugin): its trajectories and plan, if asked for."""
        mppi = _mppi_of(controller)
        if not self.enabled or not isinstance(mppi, MPPIController) or not mppi.params.visualize:
            return
        if self.markers.get_subscription_count() > 0:
            x, y = mppi.sampled_trajectories
            steps = mppi.visualizer
            sets = trajectory_markers(x, y, mppi.last_trajectory, steps.trajectory_step, steps.time_step)
            encoder = self._encoders.setdefault(frame, SphereArrayEncoder(frame))
            self.markers.publish(encoder.encode(sets))
        if self.plan.get_subscription_count() > 0:
            self.plan.publish(path_from_array(mppi.transformed_plan, frame, stamp))

    def destroy(self) -> None:
        if self.enabled:
            self.node.destroy_publisher(self.markers)
            self.node.destroy_publisher(self.plan)


class SphereArrayEncoder:
    """Serializes a MarkerArray of SPHERE markers (CDR, as rclpy would) from arrays, without Marker objects.

    A marker's bytes are: a prefix (stamp 0, frame_id, ns, id, type, action: 4-byte aligned), padding
    to 8, pose and scale (10 doubles), colour (4 floats), and a tail of empty fields that is the same
    for every marker (taken from rclpy's own serialization of a template, so the message definition
    stays rclpy's). Only the padding before the doubles depends on where a marker starts.
    """

    def __init__(self, frame: str) -> None:
        self.frame = frame
        self._templates: dict[str, tuple[bytes, bytes, bytes]] = {}  # ns → (encapsulation, prefix, tail)

    def _template(self, ns: str) -> tuple[bytes, bytes, bytes]:
        if ns not in self._templates:
            marker = _sphere(self.frame, ns, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))
            raw = serialize_message(MarkerArray(markers=[marker]))
            data = raw[4:]
            prefix = 8 + _aligned(5 + len(self.frame.encode())) + _aligned(5 + len(ns.encode())) + 12
            pad = -(4 + prefix) % 8
            tail = data[4 + prefix + pad + 96:]
            self._templates[ns] = (raw[:4], data[4: 4 + prefix], tail)
        return self._templates[ns]

    def encode(self, sets: Sequence[Any]) -> bytes:
        """The serialized MarkerArray of the spheres of ``sets`` (visualization.MarkerSet), in order.

        Within a namespace every marker after the first starts at the same offset modulo 8, so all
        but the first share one layout and are written as rows of one array."""
        total = sum(len(group.ids) for group in sets)
        encapsulation, _, tail = self._template(sets[0].namespace if sets else "")
        parts, offset = [struct.pack("<I", total)], 4  # offset: data offset where the next marker starts
        for group in sets:
            _, prefix, tail = self._template(group.namespace)
            n = len(group.ids)
            if not n:
                continue
            numbers = np.column_stack([group.centres, np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)), group.sizes])
            base = len(prefix) + 96 + len(tail) + (-len(tail) % 4)
            first = -(offset + len(prefix)) % 8
            rest = -base % 8
            parts.append(self._rows(prefix, tail, first, group.ids[:1], numbers[:1], group.colours[:1]))
            parts.append(self._rows(prefix, tail, rest, group.ids[1:], numbers[1:], group.colours[1:]))
            offset += base + first + (n - 1) * (base + rest)
        data = b"".join(parts)
        if total:  # the last marker ends the message: no padding after it
            data = data[: len(data) - (-len(tail) % 4)]
        return encapsulation + data

    @staticmethod
    def _rows(prefix: bytes, tail: bytes, pad: int, ids: Any, numbers: Any, colours: Any) -> bytes:
        """Markers of one layout: the template tiled, then their id, pose, scale and colour written in."""
        n, p = len(ids), len(prefix)
        template = np.frombuffer(prefix + bytes(pad + 96) + tail + bytes(-len(tail) % 4), dtype=np.uint8)
        rows = np.tile(template, (n, 1))
        rows[:, p - 12: p - 8] = np.asarray(ids, dtype="<i4").reshape(n, 1).view(np.uint8)
        rows[:, p + pad: p + pad + 80] = np.ascontiguousarray(numbers, dtype="<f8").view(np.uint8)
        rows[:, p + pad + 80: p + pad + 96] = np.ascontiguousarray(colours, dtype="<f4").view(np.uint8)
        return rows.tobytes()


def _aligned(n: int) -> int:
    """``n`` bytes padded to a multiple of 4."""
    return n + (-n % 4)


def _mppi_of(controller: Any) -> Any:
    """The MPPI controller itself, also behind a rotation shim."""
    return controller.primary if isinstance(controller, RotationShim) else controller


def _sphere(frame: str, namespace: str, marker_id: int, centre: Any, size: Any, rgba: Any) -> Marker:
    """One of the TrajectoryVisualizer's spheres (stamp zero: "the latest", as Nav2's)."""
    marker = Marker(ns=namespace, id=marker_id, type=Marker.SPHERE, action=Marker.ADD)
    marker.header.frame_id = frame
    marker.pose.position.x, marker.pose.position.y, marker.pose.position.z = (float(v) for v in centre)
    marker.pose.orientation.w = 1.0
    marker.scale.x, marker.scale.y, marker.scale.z = (float(v) for v in size)
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = (float(v) for v in rgba)
    return marker
