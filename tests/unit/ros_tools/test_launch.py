"""The launcher starts in order with readiness, prefixes output, fails loudly and leaves no orphans."""

from __future__ import annotations

import os
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from ros_tools.launch import Launcher, LaunchError, ProcessSpec, _Running, show_problems

PY = sys.executable


def script(body: str) -> list[str]:
    return [PY, "-u", "-c", body]


def collect() -> tuple[list[str], Launcher]:
    lines: list[str] = []
    return lines, Launcher(output=lines.append, color=False, shutdown_grace=2.0)


def test_starts_in_order_after_readiness_and_prefixes_lines():
    lines, launcher = collect()
    specs = [
        ProcessSpec("first", script("print('warming up'); print('first ready'); import time; time.sleep(30)"),
                    ready="first ready"),
        ProcessSpec("second", script("print('hello from second')"), ready="hello"),
    ]
    assert launcher.run(specs) == 0  # 'second' is required and finished with 0
    started = [line for line in lines if line.startswith("[launch] starting")]
    assert [s.split()[2].rstrip(":") for s in started] == ["first", "second"]
    second_started = "[launch] starting second: " + " ".join(specs[1].cmd)
    assert lines.index("[first] first ready") < lines.index(second_started)
    assert "[second] hello from second" in lines


def test_a_dying_process_stops_the_launch_with_its_exit_code():
    lines, launcher = collect()
    specs = [
        ProcessSpec("sleeper", script("print('ready'); import time; time.sleep(60)"), ready="ready"),
        ProcessSpec("crasher", script("import sys; print('ready'); sys.exit(3)"), ready="ready"),
    ]
    code = launcher.run(specs)
    assert code == 3
    assert any("ERROR: crasher died with exit code 3" in line for line in lines)
    assert all(r.proc.poll() is not None for r in launcher.running), "a process was left running"


def test_a_process_that_exits_right_after_its_ready_line_was_ready(monkeypatch: pytest.MonkeyPatch) -> None:
    """The output reader lags behind the exit (as on a loaded machine: CI run AH): the ready line
    still counts, and the launch ends with the process's own exit code."""
    pump = _Running._pump

    def lagging_pump(self: _Running, *args: Any) -> None:
        # The lag itself, not a wait for a condition: longer than the launcher's 0.1 s readiness poll,
        # so the launcher sees the exit before the reader has read the ready line.
        time.sleep(0.5)
        pump(self, *args)

    monkeypatch.setattr(_Running, "_pump", lagging_pump)
    lines, launcher = collect()
    quick = ProcessSpec("quick", script("import sys; print('ready'); sys.exit(3)"), ready="ready")
    assert launcher.run([quick]) == 3
    assert any("quick is ready" in line for line in lines)


def test_log_files_keep_every_line_while_the_console_shows_only_problems(tmp_path: Path) -> None:
    lines: list[str] = []
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0, log_dir=tmp_path / "logs",
                        show=show_problems)
    body = ("print('[INFO] [1.0] [n]: chatty'); print('[WARN] [1.1] [n]: careful'); "
            "print('[INFO] [1.2] [n]: ready')")
    assert launcher.run([ProcessSpec("talker", script(body), ready="ready")]) == 0
    assert (tmp_path / "logs" / "talker.log").read_text().splitlines() == [
        "[INFO] [1.0] [n]: chatty", "[WARN] [1.1] [n]: careful", "[INFO] [1.2] [n]: ready"]
    shown = [line for line in lines if line.startswith("[talker]")]
    assert shown == ["[talker] [WARN] [1.1] [n]: careful"]


def test_a_dead_process_shows_its_last_lines_and_its_log_file(tmp_path: Path) -> None:
    lines: list[str] = []
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0, log_dir=tmp_path,
                        show=show_problems)
    body = "import sys; print('ready'); [print(f'step {i}') for i in range(30)]; sys.exit(4)"
    assert launcher.run([ProcessSpec("worker", script(body), ready="ready")]) == 4
    header = next(i for i, line in enumerate(lines) if "last 15 lines of worker" in line)
    assert str(tmp_path / "worker.log") in lines[header]
    assert lines[header + 1:header + 16] == [f"[worker] step {i}" for i in range(15, 30)]


def test_readiness_timeout_and_early_exit_are_reported():
    lines, launcher = collect()
    spec = ProcessSpec("mute", script("import time; time.sleep(60)"), ready="never", ready_timeout=0.5)
    assert launcher.run([spec]) == 1
    assert any("mute was not ready after" in line and "'never'" in line for line in lines)
    lines2, launcher2 = collect()
    assert launcher2.run([ProcessSpec("quitter", script("import sys; sys.exit(5)"), ready="x")]) == 1
    assert any("quitter exited with code 5 before it was ready" in line for line in lines2)


def test_missing_executable_is_a_launch_error():
    _, launcher = collect()
    with pytest.raises(LaunchError, match="cannot start ghost"):
        launcher.start([ProcessSpec("ghost", ["/nonexistent/ghost-binary"])])


def test_stop_shuts_everything_down_and_children_of_children_too():
    lines, launcher = collect()
    # The child starts a grandchild in the same process group; shutdown must end both.
    body = ("import subprocess, sys, time; p = subprocess.Popen([sys.executable, '-c', "
            "'import time; time.sleep(60)']); print('pid', p.pid, flush=True); print('ready'); "
            "time.sleep(60)")
    timer = threading.Timer(1.0, launcher.stop)
    timer.start()
    try:
        assert launcher.run([ProcessSpec("parent", script(body), ready="ready")]) == 0
    finally:
        timer.cancel()
    grandchild = int(next(line for line in lines if line.startswith("[parent] pid")).split()[-1])
    with pytest.raises(ProcessLookupError):
        for _ in range(100):  # the grandchild may take a moment to be reaped by init
            os.kill(grandchild, 0)
            threading.Event().wait(0.05)


def test_a_slow_start_prints_live_status_lines(monkeypatch):
    monkeypatch.setattr(Launcher, "STATUS_PERIOD", 0.3)
    lines, launcher = collect()
    body = "import time; time.sleep(1.0); print('up', flush=True); time.sleep(30)"
    slow = ProcessSpec("slow", script(body),
                       ready="up", ready_timeout=20.0)
    assert launcher.run([slow], until=lambda: True) == 0
    waiting = [line for line in lines if line.startswith("[launch] waiting for slow:")]
    assert len(waiting) >= 2 and "of 20 s (until it prints 'up')" in waiting[0]
    assert any(line.startswith("[launch] slow is ready (") for line in lines)


def test_shutdown_returns_once_every_line_the_processes_wrote_has_been_read():
    """The demo prints the stack's last warnings after a failed run; the one that explains the failure
    may still be in a pipe when the run ends (CI run DJ), so shutdown reads everything first."""
    lines: list[str] = []

    def slow_output(line: str) -> None:  # a reader thread slower than the process's exit
        time.sleep(0.3)
        lines.append(line)

    launcher = Launcher(output=slow_output, color=False, shutdown_grace=2.0)
    body = ("import signal, sys, time; print('ready'); "
            "signal.signal(signal.SIGINT, lambda *_: (print('goodbye'), sys.exit(0))); time.sleep(30)")
    launcher.start([ProcessSpec("polite", script(body), ready="ready")])
    launcher.shutdown()
    assert "[polite] goodbye" in lines
