"""ProcessSpec.ready_before_next (issue 48: a fleet's stacks start side by side): the next process starts
without waiting for this one's readiness, which is still awaited before start() returns, and a process that
dies before its late-awaited readiness still fails the launch."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from ros_tools.launch import Launcher, LaunchError, ProcessSpec

PY = sys.executable


def script(body: str) -> list[str]:
    return [PY, "-u", "-c", body]


def test_processes_that_do_not_wait_start_together_and_are_all_awaited(tmp_path: Path) -> None:
    lines: list[str] = []
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    # 'a' gets ready only after 'b' has printed: with a wait between them the launch could never start b
    marker = ("import os, time\nwhile not os.path.exists({path!r}): time.sleep(0.02)\n"
              "print('ready'); time.sleep(30)")
    flag = str(tmp_path / "b_started")
    specs = [
        ProcessSpec("a", script(marker.format(path=flag)), ready="ready", ready_timeout=20.0,
                    ready_before_next=False),
        ProcessSpec("b", script(f"open({flag!r}, 'w').close(); print('ready'); import time; time.sleep(30)"),
                    ready="ready", ready_timeout=20.0, ready_before_next=False),
    ]
    try:
        launcher.start(specs)
        assert all(running.ready is not None and running.ready.is_set() for running in launcher.running)
        assert lines.index("[launch] starting b: " + " ".join(specs[1].cmd)) < lines.index("[a] ready")
        assert any(line.startswith("[launch] a is ready") for line in lines)
    finally:
        launcher.shutdown()


def test_a_late_awaited_process_that_dies_before_its_ready_line_fails_the_start() -> None:
    lines: list[str] = []
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    specs = [
        ProcessSpec("dies", script("import sys; sys.exit(4)"), ready="ready", ready_before_next=False),
        ProcessSpec("fine", script("print('ready'); import time; time.sleep(30)"), ready="ready",
                    ready_before_next=False),
    ]
    try:
        with pytest.raises(LaunchError, match="dies exited with code 4 before it was ready"):
            launcher.start(specs)
        assert any(line.startswith("[launch] starting fine") for line in lines)
    finally:
        launcher.shutdown()
