"""smacc-new (smacc_py.scaffold): the package it writes, what it refuses, and that the package's own test
passes and its graph draws, in this process. tests/system/test_smacc_new.py runs it on the ROS graph and
checks it with ruff."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from smacc_py.ros import graph_cli
from smacc_py.ros.loader import load_state_machine
from smacc_py.scaffold import class_name, main, write_package

LAYOUT = [
    "__init__.py", "clients/__init__.py", "clients/cl_heartbeat/__init__.py",
    "clients/cl_heartbeat/cl_heartbeat.py", "clients/cl_heartbeat/client_behaviors/__init__.py",
    "clients/cl_heartbeat/client_behaviors/cb_beat.py", "orthogonals/__init__.py",
    "orthogonals/or_heartbeat.py", "sm_scaffold_unit.py", "states/__init__.py", "states/st_state_1.py",
    "tests/__init__.py", "tests/test_sm_scaffold_unit.py",
]


@pytest.fixture(autouse=True)
def _restore_import_state() -> Iterator[None]:
    path, modules = list(sys.path), set(sys.modules)
    yield
    sys.path[:] = path
    for name in set(sys.modules) - modules:
        del sys.modules[name]


def test_the_package_has_smacc2s_layout_and_its_own_test_passes(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    written = write_package("sm_scaffold_unit", tmp_path)
    root = tmp_path / "sm_scaffold_unit"
    assert sorted(str(p.relative_to(root)) for p in written) == LAYOUT
    machine = load_state_machine(str(root))
    assert machine.__name__ == "SmScaffoldUnit"
    model = machine.validate()
    assert [s.__name__ for s in model.states] == ["StState1"]
    assert [o.__name__ for o in model.configured_orthogonals()] == ["OrHeartbeat"]
    test_module = importlib.import_module("sm_scaffold_unit.tests.test_sm_scaffold_unit")
    test_module.test_state_1_beats_three_times_then_starts_over()  # the generated test, as pytest would
    assert graph_cli.main([str(root)]) == 0
    assert "StState1 --> StState1 : EvCbSuccess[CbBeat, OrHeartbeat] / SUCCESS" in capsys.readouterr().out


def test_an_existing_folder_is_never_overwritten(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    existing = tmp_path / "sm_scaffold_taken"
    existing.mkdir()
    (existing / "mine.py").write_text("KEEP = 1\n")
    assert main(["sm_scaffold_taken", "--dir", str(tmp_path)]) == 2
    assert f"smacc-new: {existing} already exists; not overwriting it" in capsys.readouterr().err
    assert [p.name for p in existing.iterdir()] == ["mine.py"]


@pytest.mark.parametrize(("name", "says"), [
    ("SmUpper", "is not a lower-case Python module name"),
    ("sm-dash", "is not a lower-case Python module name"),
    ("class", "is not a lower-case Python module name"),
    ("json", "a module named 'json' can already be imported here"),
    ("smacc_py", "a module named 'smacc_py' can already be imported here"),
])
def test_names_that_would_not_import_or_would_shadow_a_module_are_refused(
        name: str, says: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main([name, "--dir", str(tmp_path)]) == 2
    assert says in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_machine_class_is_the_camel_case_of_the_package() -> None:
    assert class_name("sm_my_machine") == "SmMyMachine"
    assert class_name("sm_atomic_24hr") == "SmAtomic24hr"
