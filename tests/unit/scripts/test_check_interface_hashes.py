"""scripts/check_interface_hashes.py finds every wrong, missing or extra interface type.

Runs on a copy of interfaces/bond (two small messages) so each case takes well under a second;
no CMake, no rclpy.
"""

from __future__ import annotations

import importlib.util
import json
import shutil
import sys
from pathlib import Path
from types import ModuleType

import pytest

REPO = Path(__file__).resolve().parents[3]


def load_tool() -> ModuleType:
    path = REPO / "scripts" / "check_interface_hashes.py"
    spec = importlib.util.spec_from_file_location("check_interface_hashes", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look the module up while the class is created
    spec.loader.exec_module(module)
    return module


tool = load_tool()
Capsys = pytest.CaptureFixture[str]


@pytest.fixture
def bond_tree(tmp_path: Path) -> tuple[Path, Path]:
    """A copy of interfaces/bond and a reference holding only bond's Jazzy hashes."""
    interfaces = tmp_path / "interfaces"
    shutil.copytree(REPO / "interfaces" / "bond", interfaces / "bond")
    hashes = json.loads((REPO / "interfaces" / "type_hashes.json").read_text())["hashes"]
    reference = tmp_path / "reference.json"
    reference.write_text(json.dumps({"hashes": {k: v for k, v in hashes.items() if k.startswith("bond/")}}))
    return interfaces, reference


def run(interfaces: Path, reference: Path) -> int:
    return int(tool.main(["--interfaces", str(interfaces), "--reference", str(reference)]))


def test_unchanged_package_matches_reference(bond_tree: tuple[Path, Path], capsys: Capsys) -> None:
    assert run(*bond_tree) == 0
    assert "2/2 reference types match" in capsys.readouterr().out


def test_changed_field_type_is_a_mismatch(bond_tree: tuple[Path, Path], capsys: Capsys) -> None:
    interfaces, reference = bond_tree
    status = interfaces / "bond" / "msg" / "Status.msg"
    status.write_text(status.read_text().replace("float32 heartbeat_period", "float64 heartbeat_period"))
    assert run(interfaces, reference) == 1
    assert "MISMATCH   bond/msg/Status" in capsys.readouterr().out


def test_comment_and_constant_changes_keep_the_hash(bond_tree: tuple[Path, Path]) -> None:
    interfaces, reference = bond_tree
    constants = interfaces / "bond" / "msg" / "Constants.msg"
    constants.write_text("# another comment\n" + constants.read_text().replace("= 4.0", "= 5.0"))
    assert run(interfaces, reference) == 0


def test_missing_and_extra_types_are_reported(bond_tree: tuple[Path, Path], capsys: Capsys) -> None:
    interfaces, reference = bond_tree
    msg_dir = interfaces / "bond" / "msg"
    (msg_dir / "Constants.msg").rename(msg_dir / "Renamed.msg")
    assert run(interfaces, reference) == 1
    out = capsys.readouterr().out
    assert "MISSING    bond/msg/Constants" in out
    assert "UNEXPECTED bond/msg/Renamed" in out


def test_unknown_field_type_names_the_file(bond_tree: tuple[Path, Path], capsys: Capsys) -> None:
    interfaces, reference = bond_tree
    (interfaces / "bond" / "msg" / "Broken.msg").write_text("no_such_pkg/Thing value\n")
    assert run(interfaces, reference) == 1
    assert "no_such_pkg" in capsys.readouterr().err
