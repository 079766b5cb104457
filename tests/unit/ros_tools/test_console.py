"""StackConsole: the stack's lines kept unless verbose, errors live, problems after a failure, and a
live line that never garbles a printed one."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from ros_tools.console import StackConsole
from ros_tools.status_line import StatusLine


def test_a_calm_console_keeps_the_stack_and_shows_errors_live(capsys: pytest.CaptureFixture[str]) -> None:
    console = StackConsole(verbose=False, name="demo")
    console.stack("[nav] [nav2] [INFO] [1.0] [amcl]: chatty")
    console.stack("[nav] [nav2] [WARN] [1.1] [planner_server]: slow")
    console.stack("[nav] [nav2] [ERROR] [1.2] [map_server]: broken")
    assert capsys.readouterr().out.splitlines() == ["[nav] [nav2] [ERROR] [1.2] [map_server]: broken"]
    console.show_problems(Path("artifacts/logs"))
    shown = capsys.readouterr().out.splitlines()
    assert shown[0].startswith("[demo] the stack's last 2 warnings and errors; full logs: artifacts/logs/")
    assert shown[1:] == ["[nav] [nav2] [WARN] [1.1] [planner_server]: slow",
                         "[nav] [nav2] [ERROR] [1.2] [map_server]: broken"]


def test_verbose_streams_everything(capsys: pytest.CaptureFixture[str]) -> None:
    console = StackConsole(verbose=True, name="demo")
    console.stack("[nav] [nav2] [INFO] [1.0] [amcl]: chatty")
    console.show_problems(Path("logs"))
    assert capsys.readouterr().out.splitlines() == ["[nav] [nav2] [INFO] [1.0] [amcl]: chatty"]


def test_a_printed_line_first_blanks_the_live_line() -> None:
    stream = io.StringIO()
    console = StackConsole(verbose=False, name="demo", status=StatusLine(stream, period=0.0, live=True))
    console.live("StRotate | sim 20.0 s")
    assert stream.getvalue().startswith("\rStRotate | sim 20.0 s")
    console.say("[demo] a transition")
    *_, blank, after = stream.getvalue().rsplit("\r", 2)
    assert after == "" and blank.strip() == "" and len(blank) >= len("StRotate | sim 20.0 s")
