"""The README stays true: every command it names exists, starts, and is exercised by a test.

`make test` and `make demo` are run by CI and by the demo's system test; the console commands in the
README are checked here: each one is a registered entry point whose function imports, answers
``--help`` with exit status 0, and is run by at least one other test file (by its command name or
its module).
"""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
_TABLE = (REPO / "pyproject.toml").read_text().split("[project.scripts]", 1)[1].split("\n[", 1)[0]
SCRIPTS: dict[str, str] = dict(re.findall(r'^([\w-]+) = "([\w.]+:\w+)"', _TABLE, re.MULTILINE))
README = (REPO / "README.md").read_text()

pytestmark = pytest.mark.ros


def readme_commands() -> list[str]:
    """Registered console commands that start a line of a code block or an inline code span."""
    blocks = re.findall(r"```[a-z]*\n(.*?)```", README, re.DOTALL)
    prose = re.sub(r"```.*?```", "", README, flags=re.DOTALL)
    candidates = [line for block in blocks for line in block.splitlines()] + re.findall(r"`([^`]+)`", prose)
    firsts = {text.split()[0] for text in candidates if text.split()}
    return sorted(first for first in firsts if first in SCRIPTS)


def test_the_readme_names_the_main_commands():
    named = readme_commands()
    for command in ("navsuite-demo", "nav-bringup", "nav-goal", "sim2d", "smacc-run", "ros2py"):
        assert command in named


@pytest.mark.parametrize("command", readme_commands())
def test_each_readme_command_imports_answers_help_and_is_tested(command: str):
    module_name, function_name = SCRIPTS[command].split(":")
    assert callable(getattr(importlib.import_module(module_name), function_name))
    code = ("import sys; from importlib import import_module; "
            f"sys.argv = [{command!r}, '--help']; import_module({module_name!r}).{function_name}()")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=REPO)
    assert done.returncode == 0, f"{command} --help failed:\n{done.stdout}\n{done.stderr}"
    assert "usage" in (done.stdout + done.stderr).lower()
    this_file = Path(__file__).resolve()
    users = [path for path in (REPO / "tests").rglob("*.py") if path.resolve() != this_file
             and (command in path.read_text() or module_name in path.read_text())]
    assert users, f"no test runs {command} ({module_name})"
