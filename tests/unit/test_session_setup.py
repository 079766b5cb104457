"""The test session's own setup (tests/conftest.py): where a test's process logs go."""

from __future__ import annotations

import os

import pytest

from ros_tools.launch import default_log_dir


def test_each_test_has_its_own_process_log_directory(request) -> None:
    log_dir = default_log_dir()
    assert log_dir.name == request.node.name
    assert log_dir.parent.name == "tests_unit_test_session_setup.py"
    assert log_dir.parent.parent.name.startswith(f"navsuite-logs-{os.environ['ROS_DOMAIN_ID']}-")


@pytest.mark.parametrize("case", ["a/b c"])
def test_a_parametrized_test_gets_a_directory_a_path_can_hold(case: str) -> None:
    log_dir = default_log_dir()
    assert log_dir.name == "test_a_parametrized_test_gets_a_directory_a_path_can_hold_a_b_c_"
    assert log_dir.is_absolute()
