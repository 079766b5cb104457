"""How many DDS participants this process holds, read from its UDP sockets (Linux /proc).

Why: with ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, Fast DDS looks for peers on a bounded range of
participant ids, so a test worker that keeps old participants (a node its test destroyed but something
still holds) pushes the next processes' ids out of that range and they are never discovered. CI runs
18 and 19 went red that way, far from the test that leaked. Each participant binds two unicast
metatraffic ports at 7400 + 250 * domain + 10 + 2 * id (+1), the RTPS well-known port rule.
"""

from __future__ import annotations

import os

#: participant ids counted (Fast DDS gives each new participant of a domain the lowest free id)
IDS = 120


def own_participants(domain: int) -> int:
    """DDS participants of ``domain`` whose ports this process has bound."""
    inodes = set()
    for fd in os.listdir("/proc/self/fd"):
        try:
            link = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:  # closed while we looked
            continue
        if link.startswith("socket:["):
            inodes.add(link[len("socket:["):-1])
    first = 7400 + 250 * domain + 10
    ports = set()
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(table, encoding="ascii") as f:
                rows = f.read().splitlines()[1:]
        except OSError:
            continue
        for row in rows:
            fields = row.split()
            port = int(fields[1].rsplit(":", 1)[1], 16)
            if fields[9] in inodes and first <= port < first + 2 * IDS:
                ports.add(port)
    return len({(port - first) // 2 for port in ports})
