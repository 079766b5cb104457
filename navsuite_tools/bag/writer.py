"""Writing ROS 2 messages into an MCAP file that ``ros2 bag`` and Foxglove open.

The file follows the MCAP ``ros2`` profile as rosbag2's MCAP storage plugin writes it: schemas
``pkg/msg/Type`` with encoding ``ros2msg`` (:mod:`navsuite_tools.bag.schema`), channels with message
encoding ``cdr`` and the metadata ``offered_qos_profiles`` (plus ``topic_type_hash`` when known),
messages with log and publish time in nanoseconds. Chunks are compressed (zstd by default) and
the summary (statistics, chunk and message indexes) is written on :meth:`BagWriter.close`, so
readers can seek and ``info`` needs no scan.
"""

from __future__ import annotations

from pathlib import Path
from types import TracebackType
from typing import IO, Any

from mcap.writer import CompressionType, Writer
from rclpy.serialization import serialize_message

from navsuite_tools.bag.schema import SCHEMA_ENCODING, message_definition
from ros_tools.types import parse_type_name, type_name_of

PROFILE = "ros2"
MESSAGE_ENCODING = "cdr"
LIBRARY = "navsuite navsuite_tools.bag"
COMPRESSIONS = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
#: Uncompressed bytes per chunk (1 MiB, the mcap default; rosbag2 uses the same size).
CHUNK_SIZE = 1024 * 1024


class BagWriter:
    """An open MCAP file; topics are added once, then messages are written as they arrive.

    Not thread-safe: the recorder calls it from one executor thread.
    """

    def __init__(self, path: str | Path, compression: str = "zstd") -> None:
        """Create (or overwrite) ``path``.

        Raises:
            ValueError: unknown compression, or the file cannot be created.
        """
        if compression not in COMPRESSIONS:
            raise ValueError(f"compression must be one of {', '.join(COMPRESSIONS)}, got '{compression}'")
        self.path = Path(path)
        try:
            self._stream: IO[bytes] = self.path.open("wb")
        except OSError as exc:
            raise ValueError(f"cannot create {self.path}: {exc.strerror}") from None
        self._writer = Writer(self._stream, chunk_size=CHUNK_SIZE, compression=COMPRESSIONS[compression])
        self._writer.start(profile=PROFILE, library=LIBRARY)
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, tuple[int, str]] = {}
        self._sequence: dict[str, int] = {}
        self.closed = False

    def add_topic(self, topic: str, type_name: str, offered_qos: str = "", type_hash: str = "") -> None:
        """Declare a topic and its type (a second call for the same topic is ignored).

        Raises:
            ValueError: unknown type or missing ``.msg`` definition.
        """
        if topic in self._channels:
            return
        full_type = str(parse_type_name(type_name, "msg"))
        schema_id = self._schemas.get(full_type)
        if schema_id is None:
            text = message_definition(full_type)
            schema_id = self._writer.register_schema(full_type, SCHEMA_ENCODING, text.encode("utf-8"))
            self._schemas[full_type] = schema_id
        metadata = {"offered_qos_profiles": offered_qos}
        if type_hash:
            metadata["topic_type_hash"] = type_hash
        channel_id = self._writer.register_channel(topic, MESSAGE_ENCODING, schema_id, metadata)
        self._channels[topic] = (channel_id, full_type)
        self._sequence[topic] = 0

    def write(self, topic: str, data: bytes, log_time_ns: int, publish_time_ns: int | None = None) -> None:
        """Write one CDR-serialized message of an added topic.

        Raises:
            ValueError: the topic was not added.
        """
        entry = self._channels.get(topic)
        if entry is None:
            raise ValueError(f"topic '{topic}' was not added to {self.path}")
        sequence = self._sequence[topic]
        self._sequence[topic] = sequence + 1
        self._writer.add_message(
            entry[0], log_time=int(log_time_ns), data=data,
            publish_time=int(log_time_ns if publish_time_ns is None else publish_time_ns), sequence=sequence,
        )

    def write_message(self, topic: str, msg: Any, log_time_ns: int) -> None:
        """Serialize and write a message object, adding its topic on first use."""
        if topic not in self._channels:
            self.add_topic(topic, type_name_of(msg))
        self.write(topic, serialize_message(msg), log_time_ns)

    def close(self) -> None:
        """Write the summary section and close the file (safe to call twice)."""
        if self.closed:
            return
        self.closed = True
        try:
            self._writer.finish()
        finally:
            self._stream.close()

    def __enter__(self) -> BagWriter:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None,
    ) -> None:
        self.close()
