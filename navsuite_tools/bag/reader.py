"""Reading ROS 2 MCAP files: topics, counts and time range, and the messages in time order.

Works on files written by :mod:`navsuite_tools.bag.writer`, by ``ros2 bag record -s mcap`` and by other
``ros2``-profile writers. A file without a summary section or cut short (a recorder that was
killed) is read by scanning it up to the last complete record; it is then ``truncated``. Every
failure to read becomes a :class:`BagError` whose message names the file.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import IO, Any

from mcap.exceptions import EndOfFile
from mcap.reader import McapReader, NonSeekingReader, make_reader
from mcap.records import Channel, Message, Schema
from rclpy.serialization import deserialize_message

from ros_tools.types import import_type


class BagError(ValueError):
    """A recording cannot be opened, is malformed, or does not hold what was asked for."""


@dataclass(frozen=True)
class TopicInfo:
    """One recorded topic.

    Attributes:
        name: topic name.
        type: ``pkg/msg/Type`` (the schema name).
        count: number of messages.
        encoding: message encoding (``cdr`` for ROS 2).
        offered_qos: the ``offered_qos_profiles`` text recorded with the channel ("" if none).
    """

    name: str
    type: str
    count: int
    encoding: str
    offered_qos: str


@dataclass(frozen=True)
class BagMessage:
    """One recorded message: CDR bytes plus the log and publish time (ns)."""

    topic: str
    type: str
    log_time: int
    publish_time: int
    data: bytes


class BagReader:
    """An MCAP file opened for reading (use as a context manager, or call :meth:`close`)."""

    def __init__(self, path: str | Path) -> None:
        """Open ``path`` and read its summary (or scan it when the summary is missing).

        Raises:
            BagError: missing, unreadable or malformed file.
        """
        self.path = Path(path)
        try:
            self._stream: IO[bytes] = self.path.open("rb")
        except OSError as exc:
            raise BagError(f"cannot open {self.path}: {exc.strerror}") from None
        try:
            self._reader: McapReader = make_reader(self._stream)
            self.profile = self._reader.get_header().profile
            self._load_summary()
        except BagError:
            self.close()
            raise
        except Exception as exc:  # the mcap package raises many types for malformed input
            self.close()
            raise BagError(f"{self.path} is not a readable MCAP file: {exc}") from None

    def _load_summary(self) -> None:
        self.truncated = False
        try:
            summary = self._reader.get_summary()
        except EndOfFile:
            summary, self.truncated = None, True
        self._scanned = summary is None or summary.statistics is None
        if not self._scanned:
            assert summary is not None and summary.statistics is not None
            stats = summary.statistics
            recorded = {cid: stats.channel_message_counts.get(cid, 0) for cid in summary.channels}
            self._set_topics(summary.channels.values(), summary.schemas, recorded)
            self.message_count = stats.message_count
            self.start_ns = stats.message_start_time if stats.message_count else 0
            self.end_ns = stats.message_end_time if stats.message_count else 0
            return
        channels: dict[int, Channel] = {}
        schemas: dict[int, Schema] = {}
        counts: dict[int, int] = {}
        start, end, total = None, None, 0
        for schema, channel, message in self._scan():
            channels[channel.id] = channel
            if schema is not None:
                schemas[schema.id] = schema
            counts[channel.id] = counts.get(channel.id, 0) + 1
            start = message.log_time if start is None else min(start, message.log_time)
            end = message.log_time if end is None else max(end, message.log_time)
            total += 1
        self._set_topics(channels.values(), schemas, counts)
        self.message_count, self.start_ns, self.end_ns = total, start or 0, end or 0

    def _scan(self) -> Iterator[tuple[Schema | None, Channel, Message]]:
        """All messages in file order, stopping quietly at a cut-off end (sets ``truncated``)."""
        self._stream.seek(0)
        try:
            yield from NonSeekingReader(self._stream).iter_messages(log_time_order=False)
        except EndOfFile:
            self.truncated = True

    def _set_topics(
        self, channels: Iterable[Channel], schemas: dict[int, Schema], counts: dict[int, int],
    ) -> None:
        topics: dict[str, TopicInfo] = {}
        for channel in sorted(channels, key=lambda c: c.id):
            schema = schemas.get(channel.schema_id)
            count = counts.get(channel.id, 0)
            previous = topics.get(channel.topic)
            if previous is not None:
                count += previous.count
            topics[channel.topic] = TopicInfo(
                name=channel.topic,
                type=previous.type if previous else (schema.name if schema else ""),
                count=count,
                encoding=channel.message_encoding,
                offered_qos=channel.metadata.get("offered_qos_profiles", ""),
            )
        self.topics = dict(sorted(topics.items()))

    @property
    def duration_ns(self) -> int:
        """Time from the first to the last message (log time, ns)."""
        return self.end_ns - self.start_ns

    def check_topics(self, topics: Iterable[str]) -> list[str]:
        """Return ``topics`` unchanged if all were recorded.

        Raises:
            BagError: a topic is not in the file (the recorded topics are listed).
        """
        wanted = list(topics)
        unknown = [topic for topic in wanted if topic not in self.topics]
        if unknown:
            raise BagError(
                f"unknown topic {', '.join(unknown)}: not in {self.path} "
                f"(recorded: {', '.join(self.topics) or 'none'})"
            )
        return wanted

    def messages(self, topics: Iterable[str] | None = None) -> Iterator[BagMessage]:
        """Messages in log-time order, optionally only those of ``topics``.

        Raises:
            BagError: an unknown topic, or the file is damaged past its summary.
        """
        selected = None if topics is None else self.check_topics(topics)
        if selected is not None and not selected:
            return
        try:
            if self._scanned:  # no summary: read everything wanted, then order it by log time
                wanted = None if selected is None else set(selected)
                found = [r for r in self._scan() if wanted is None or r[1].topic in wanted]
                records: Iterable[tuple[Schema | None, Channel, Message]] = sorted(
                    found, key=lambda r: r[2].log_time)
            else:
                records = self._reader.iter_messages(topics=selected, log_time_order=True)
            for schema, channel, message in records:
                yield BagMessage(
                    topic=channel.topic,
                    type=schema.name if schema is not None else self.topics[channel.topic].type,
                    log_time=message.log_time,
                    publish_time=message.publish_time,
                    data=message.data,
                )
        except BagError:
            raise
        except Exception as exc:
            raise BagError(f"{self.path} is damaged: {exc}") from None

    def decoded(self, topics: Iterable[str] | None = None) -> Iterator[tuple[BagMessage, Any]]:
        """Messages with their deserialized ROS message objects.

        Raises:
            BagError: a type cannot be imported, or bytes do not decode as that type.
        """
        classes: dict[str, Any] = {}
        for item in self.messages(topics):
            cls = classes.get(item.type)
            if cls is None:
                try:
                    cls = classes[item.type] = import_type(item.type, "msg")
                except ValueError as exc:
                    raise BagError(f"{self.path}: topic {item.topic}: {exc}") from None
            try:
                yield item, deserialize_message(item.data, cls)
            except Exception as exc:
                raise BagError(f"{self.path}: topic {item.topic}: cannot decode {item.type}: {exc}") from None

    def close(self) -> None:
        """Close the file."""
        self._stream.close()

    def __enter__(self) -> BagReader:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None,
    ) -> None:
        self.close()
