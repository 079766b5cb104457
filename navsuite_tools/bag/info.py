"""``navsuite-bag info``: what a recording holds, laid out like ``ros2 bag info``."""

from __future__ import annotations

import time

from navsuite_tools.bag.reader import BagReader


def _size(n_bytes: int) -> str:
    size = float(n_bytes)
    for unit in ("B", "KiB", "MiB", "GiB"):
        if size < 1024 or unit == "GiB":
            return f"{size:.1f} {unit}" if unit != "B" else f"{n_bytes} B"
        size /= 1024
    return f"{n_bytes} B"


def _stamp(ns: int) -> str:
    seconds, rest = divmod(ns, 1_000_000_000)
    return time.strftime("%b %d %Y %H:%M:%S", time.localtime(seconds)) + f".{rest:09d} ({seconds}.{rest:09d})"


def format_info(reader: BagReader) -> str:
    """The summary text: file, size, duration, start, end, message count, and one line per topic."""
    seconds, rest = divmod(reader.duration_ns, 1_000_000_000)
    lines = [
        f"Files:             {reader.path.name}",
        f"Bag size:          {_size(reader.path.stat().st_size)}",
        "Storage id:        mcap",
        f"Profile:           {reader.profile or '(none)'}",
        f"Duration:          {seconds}.{rest:09d}s",
        f"Start:             {_stamp(reader.start_ns)}",
        f"End:               {_stamp(reader.end_ns)}",
        f"Messages:          {reader.message_count}",
    ]
    if reader.truncated:
        lines.append("Truncated:         yes (no summary; read up to the last complete record)")
    width = max((len(name) for name in reader.topics), default=0)
    label = "Topic information: "
    for index, info in enumerate(reader.topics.values()):
        prefix = label if index == 0 else " " * len(label)
        lines.append(
            f"{prefix}Topic: {info.name:<{width}} | Type: {info.type} | Count: {info.count} | "
            f"Serialization Format: {info.encoding}"
        )
    if not reader.topics:
        lines.append(label)
    return "\n".join(lines)
