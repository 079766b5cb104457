"""A throwaway Ray cluster on this machine for the farm's Ray tests: a head and one worker node.

Every process of it carries ``TAG=<its temp dir>`` in its environment, so it can be stopped, and
checked gone, without touching any other Ray on the machine (``ray stop`` would kill them all). Ports
are picked free; the temp dir is short because Ray puts Unix sockets under it (107-byte path limit).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

from navsuite_tools.scenarios.executor import processes_with_env

TAG = "NAVSUITE_RAY_TEST"
RAY = str(Path(sys.executable).with_name("ray"))
OBJECT_STORE = 100 * 1024 * 1024  # bytes per node: the artifacts of a few short scenarios
#: wall s between SIGTERM and SIGKILL. Short: the workers and agents end within 0.2 s of SIGTERM, but
#: the raylets take 10 s and gcs_server and the autoscaler outlast 20 s (measured idle, 2026-11-29), so a
#: longer grace only delays the SIGKILL they get anyway (it was 5 s of the Ray tests' teardown).
TERM_GRACE = 1.0
KILL_WAIT = 5.0  # wall s for SIGKILLed processes to be gone (the loop ends as soon as they are)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _node_ports() -> list[str]:
    """A node's options: one CPU, a small object store, no dashboard, and a free port where Ray's
    default (52365) may be held by another cluster on this machine."""
    return ["--dashboard-agent-listen-port", str(free_port()),
            "--num-cpus", "1", "--object-store-memory", str(OBJECT_STORE), "--disable-usage-stats"]


def _ray_start(env: dict[str, str], *options: str) -> None:
    """``ray start`` a node on 127.0.0.1; AssertionError with Ray's own words when it fails."""
    done = subprocess.run([RAY, "start", "--node-ip-address", "127.0.0.1", *options, *_node_ports()],
                          env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"ray start {' '.join(options)} failed:\n{done.stdout}{done.stderr}"


def cluster_processes(temp_dir: Path) -> list[int]:
    return processes_with_env(f"{TAG}={temp_dir}")


def stop(temp_dir: Path) -> list[int]:
    """SIGTERM every process of the cluster, SIGKILL what is left after TERM_GRACE s; the survivors."""
    for sig, wait in ((signal.SIGTERM, TERM_GRACE), (signal.SIGKILL, KILL_WAIT)):
        for pid in cluster_processes(temp_dir):
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.kill(pid, sig)
        deadline = time.monotonic() + wait
        while cluster_processes(temp_dir) and time.monotonic() < deadline:
            time.sleep(0.2)
    return cluster_processes(temp_dir)


@contextlib.contextmanager
def local_cluster(env: dict[str, str]) -> Iterator[tuple[str, dict[str, str]]]:
    """Start the cluster (its processes inherit ``env`` plus the tag); its address and that environment.

    On exit the cluster is stopped; AssertionError if one of its processes survives that.
    """
    temp_dir = Path(tempfile.mkdtemp(prefix="nvray-", dir="/tmp"))
    tagged = dict(env, **{TAG: str(temp_dir)}, RAY_USAGE_STATS_ENABLED="0")
    address = f"127.0.0.1:{free_port()}"
    try:
        _ray_start(tagged, "--head", "--port", address.rsplit(":", 1)[1], "--temp-dir", str(temp_dir),
                   "--include-dashboard=false")
        _ray_start(tagged, "--address", address)
        yield address, tagged
    finally:
        survivors = stop(temp_dir)
        shutil.rmtree(temp_dir, ignore_errors=True)
    assert survivors == [], f"Ray processes left behind: {survivors}"
