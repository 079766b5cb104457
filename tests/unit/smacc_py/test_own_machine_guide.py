"""docs/smacc_own_machine.md's mode-state example and its MachineHarness test run as written.

The guide's blocks are run in one fresh module, the test block with its package-relative import
(``from .. import SmModes``) taken from that module instead. The rclpy example is the scaffold's
layout and is what tests/system/test_smacc_new.py checks as a process.
"""

from __future__ import annotations

import re
import sys
import types
from collections.abc import Iterator

import pytest

from navsuite_testing.ros import REPO

GUIDE = REPO / "docs" / "smacc_own_machine.md"


def _blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", GUIDE.read_text(), flags=re.S)


@pytest.fixture
def guide_module() -> Iterator[types.ModuleType]:
    module = types.ModuleType("smacc_guide_example")
    sys.modules[module.__name__] = module
    yield module
    del sys.modules[module.__name__]


def test_the_mode_state_example_and_its_test_run_as_written(guide_module: types.ModuleType) -> None:
    [modes] = [b for b in _blocks() if "class SmModes(" in b]
    [test] = [b for b in _blocks() if "def test_recovery_resumes_where_the_run_mode_was" in b]
    exec(compile(modes, f"{GUIDE}:SmModes", "exec"), guide_module.__dict__)
    assert "from .. import SmModes" in test
    exec(compile(test.replace("from .. import SmModes", ""), f"{GUIDE}:test", "exec"), guide_module.__dict__)
    guide_module.test_recovery_resumes_where_the_run_mode_was()
    assert sorted(s.__name__ for s in guide_module.SmModes.validate().states) == [
        "MsRecoveryMode", "MsRunMode", "StiStep1", "StiStep2"]
