"""Running ``ros2py`` as a user's shell would, and reading its ros2-style output.

The CLI runs as a child process (``python -m navsuite_tools.cli.main``) that inherits the test's
ROS_DOMAIN_ID and discovery range. Shared by the CLI's integration tests (fake nodes) and the
system tests that drive the real stack with it.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from typing import Any

import yaml

from navsuite_testing.ros import start_python

CLI = "navsuite_tools.cli.main"
#: Generous bounds for a loaded 2-core machine; a passing run is much faster.
DISCOVERY = ["--timeout", "15"]
PROCESS_TIMEOUT = 40.0


@dataclass
class CliResult:
    """Exit code and combined stdout+stderr of one finished CLI run."""

    code: int
    output: str

    @property
    def lines(self) -> list[str]:
        return self.output.splitlines()

    def blocks(self, title: str) -> list[Any]:
        """Every ``<title>:`` block (its 4-space indented YAML lines) parsed, in order.

        ``action send_goal`` prints ``Sending goal:``, ``Feedback:`` (with --feedback) and ``Result:``.
        """
        found = re.findall(rf"^{re.escape(title)}:\n((?:    .*\n)+)", self.output, re.MULTILINE)
        return [yaml.safe_load(text) for text in found]


def run_cli(*args: str, timeout: float = PROCESS_TIMEOUT) -> CliResult:
    """Run ``ros2py <args>`` to completion (fails the test if it takes longer than ``timeout`` s)."""
    proc = start_python(CLI, args)
    try:
        output, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        output, _ = proc.communicate()
        raise AssertionError(f"ros2py {' '.join(args)} did not finish in {timeout} s:\n{output}") from None
    return CliResult(proc.returncode, output)
