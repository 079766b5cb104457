"""Live stream of ROS topics to Foxglove over its WebSocket protocol (``navsuite-bag foxglove``).

Built on the official Foxglove SDK (PyPI ``foxglove-sdk``, import name ``foxglove``), an optional
dependency: it is imported only when streaming starts, and a missing package is reported as one
line instead of a traceback.

Topic selection, discovery (every 1 s, so topics that appear later are streamed too), QoS
matching and raw CDR delivery are the recorder's (:class:`navsuite_tools.bag.recorder.Recorder`); only
its sink differs. Each topic becomes one Foxglove channel with message encoding ``cdr`` and a
``ros2msg`` schema (the same definition text an MCAP recording carries), so Foxglove decodes the
bytes exactly as it decodes a recorded bag. Messages are logged with their receive time on the
node clock in nanoseconds.

The server binds to loopback by default: the stream carries every selected topic unauthenticated,
so exposing it on a network interface is an explicit ``--host`` choice.
"""

from __future__ import annotations

import os
import threading
import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter

from navsuite_tools.bag.reader import BagError
from navsuite_tools.bag.recorder import SPIN_SLICE, Recorder, RecordOptions, spin_for
from navsuite_tools.bag.schema import SCHEMA_ENCODING, message_definition
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.runner import ros_process
from ros_tools.status_line import StatusLine, topic_counts
from ros_tools.types import parse_type_name

#: Message encoding of every channel: the subscriptions deliver serialized CDR bytes.
MESSAGE_ENCODING = "cdr"
#: Seconds (wall clock) between graph polls for new topics: cheap enough, and quick for a human.
DISCOVERY_PERIOD = 1.0
SDK_MISSING = "the foxglove package is not installed: pip install foxglove-sdk"


class SdkMissingError(RuntimeError):
    """The optional ``foxglove`` package cannot be imported."""


def load_sdk() -> ModuleType:
    """The ``foxglove`` module.

    Raises:
        SdkMissingError: it is not installed.
    """
    try:
        import foxglove
    except ImportError:
        raise SdkMissingError(SDK_MISSING) from None
    return foxglove


@dataclass(frozen=True)
class FoxgloveOptions:
    """What to stream and where to serve it.

    Attributes:
        selection: the topics, as for recording (``output`` is unused; ``discovery_period`` is the
            graph poll period in wall seconds; ``use_sim_time`` stamps with /clock time).
        host: address the WebSocket server binds to (loopback by default).
        port: TCP port; 0 picks a free one.
    """

    selection: RecordOptions
    host: str = "127.0.0.1"
    port: int = 8765

    def __post_init__(self) -> None:
        if not self.host:
            raise ValueError("host must not be empty")
        if not 0 <= self.port <= 65535:
            raise ValueError(f"port must be in 0..65535, got {self.port}")


class FoxgloveSink:
    """A :class:`~navsuite_tools.bag.recorder.TopicSink` that logs to Foxglove channels of one SDK context."""

    def __init__(self, sdk: ModuleType, context: Any) -> None:
        self._sdk = sdk
        self._context = context
        self._channels: dict[str, Any] = {}

    def add_topic(self, topic: str, type_name: str, offered_qos: str = "", type_hash: str = "") -> None:
        """Create the topic's channel (a second call for the same topic is ignored).

        Raises:
            ValueError: unknown type or missing ``.msg`` definition.
        """
        if topic in self._channels:
            return
        full_type = str(parse_type_name(type_name, "msg"))
        schema = self._sdk.Schema(name=full_type, encoding=SCHEMA_ENCODING,
                                  data=message_definition(full_type).encode("utf-8"))
        self._channels[topic] = self._sdk.Channel(topic, schema=schema, message_encoding=MESSAGE_ENCODING,
                                                  context=self._context)

    def write(self, topic: str, data: bytes, log_time_ns: int) -> None:
        """Send one CDR message to the clients subscribed to ``topic`` (none: dropped cheaply)."""
        self._channels[topic].log(data, log_time=int(log_time_ns))

    def close(self) -> None:
        """Close every channel (clients see them unadvertised)."""
        for channel in self._channels.values():
            channel.close()
        self._channels.clear()


class FoxgloveBridge:
    """A node that subscribes like the recorder, and the SDK's WebSocket server that streams it.

    ``context`` is an initialised rclpy Context (tests pass their own). :meth:`start` spins the
    node in a background thread (the main thread redraws the status); :meth:`close` stops the
    server and the spinning, then destroys the node. The executor is ``selection.executor``.
    """

    def __init__(self, options: FoxgloveOptions, context: Any, sdk: ModuleType | None = None) -> None:
        sdk = sdk or load_sdk()
        fox_context = sdk.Context()
        self.sink = FoxgloveSink(sdk, fox_context)
        try:
            self.server = sdk.start_server(name="navsuite-bag", host=options.host, port=options.port,
                                           context=fox_context)
        except RuntimeError as exc:  # FoxgloveError: port taken, unknown host
            raise BagError(f"cannot serve on {options.host}:{options.port}: {exc}") from None
        self._host = options.host
        selection = options.selection
        self.node = Node(f"foxglove_bridge_{os.getpid()}", context=context,
                         parameter_overrides=[Parameter("use_sim_time", value=selection.use_sim_time)])
        self.executor = make_executor(selection.executor, context)
        self.executor.add_node(self.node)
        self._stopping = False
        self.recorder = Recorder(self.node, self.sink, selection)
        self.node.create_timer(selection.discovery_period, self.recorder.discover,
                               clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._thread = threading.Thread(target=self._spin, name="foxglove-ros", daemon=True)

    @property
    def url(self) -> str:
        """The address to open in Foxglove (``ws://host:port``)."""
        host = f"[{self._host}]" if ":" in self._host else self._host
        return f"ws://{host}:{self.server.port}"

    def _spin(self) -> None:
        # Slices, not executor.spin(): on this rclpy the EventsExecutor's spin() without a timeout
        # never runs a callback (and holds the GIL); a slice also lets close() stop the loop.
        while not self._stopping and self.executor.context.ok():
            try:
                spin_for(self.executor, SPIN_SLICE)
            except ExternalShutdownException:  # the context was shut down under us
                return
            except Exception as exc:  # one bad message must not stop the stream
                if not self.executor.context.ok():
                    return
                self.node.get_logger().error(f"foxglove: a callback raised {exc!r}")

    def start(self) -> FoxgloveBridge:
        self.recorder.discover()
        self._thread.start()
        return self

    def close(self) -> None:
        self.server.stop()
        self._stopping = True
        if self._thread.is_alive():
            self._thread.join(timeout=5.0)
        self.executor.shutdown(timeout_sec=5.0)
        self.sink.close()
        self.node.destroy_node()


def run_foxglove(options: FoxgloveOptions, status: StatusLine | None = None) -> dict[str, int]:
    """Stream until Ctrl-C/SIGTERM (KeyboardInterrupt); returns the message count per topic.

    Raises:
        SdkMissingError: the ``foxglove`` package is not installed (checked before ROS starts).
        BagError: the server cannot bind to ``host:port``.
    """
    sdk = load_sdk()
    status = status or StatusLine()
    with ros_process(context=rclpy.Context(), handle_signals=False) as process:  # Ctrl-C ends the loop
        bridge = FoxgloveBridge(options, process.context, sdk).start()
        try:
            print(f"streaming to Foxglove: open {bridge.url} (Open connection > Foxglove WebSocket)",
                  flush=True)
            started = time.monotonic()
            while True:
                time.sleep(0.25)  # the executor thread does the work; this only redraws the status
                counts = dict(bridge.recorder.counts)
                status.update(f"streaming {time.monotonic() - started:6.1f} s  {sum(counts.values())} msgs  "
                              f"{topic_counts(counts)}")
        except KeyboardInterrupt:
            pass
        finally:
            bridge.close()
    counts = dict(bridge.recorder.counts)
    status.finish(f"streamed {sum(counts.values())} messages on {len(counts)} topics")
    return counts
