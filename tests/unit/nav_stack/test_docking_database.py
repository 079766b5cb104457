"""The dock database: dock files and fields (errors name the source, dock and field), lookups."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.docking.database import (
    Dock,
    DockDatabase,
    DockDatabaseError,
    dock_from_fields,
    docks_from_yaml,
    load_dock_file,
)
from nav_stack.core.docking.errors import DockErrorCode, DockNotInDB, DockNotValid
from nav_stack.core.geometry import Pose2D

GOOD_FILE = """
docks:
  home_dock:
    type: simple_charging_dock
    frame: map
    pose: [0.3, 0.3, 0.0]
  flex_dock1:
    type: simple_charging_dock
    pose: [10.0, 10.0, 1]
    id: 42
"""


def test_a_dock_file_is_read(tmp_path: Path) -> None:
    path = tmp_path / "docks.yaml"
    path.write_text(GOOD_FILE)
    docks = load_dock_file(path)
    assert docks["home_dock"] == Dock("home_dock", "simple_charging_dock", "map", Pose2D(0.3, 0.3, 0.0))
    assert docks["flex_dock1"].frame == "map"  # Nav2's default frame
    assert (docks["flex_dock1"].pose, docks["flex_dock1"].id) == (Pose2D(10.0, 10.0, 1.0), "42")


@pytest.mark.parametrize(("fields", "field"), [
    ({"pose": [0.0, 0.0, 0.0]}, "'type'"),
    ({"type": "", "pose": [0.0, 0.0, 0.0]}, "'type'"),
    ({"type": "simple_charging_dock"}, "'pose'"),
    ({"type": "simple_charging_dock", "pose": [0.0, 0.0]}, "'pose'"),
    ({"type": "simple_charging_dock", "pose": [0.0, "a", 0.0]}, "'pose'"),
    ({"type": "simple_charging_dock", "pose": [0.0, float("nan"), 0.0]}, "'pose'"),
    ({"type": "simple_charging_dock", "pose": [0.0, 0.0, 0.0], "frame": ""}, "'frame'"),
])
def test_malformed_dock_fields_name_the_source_dock_and_field(fields: dict[str, object], field: str) -> None:
    with pytest.raises(DockDatabaseError) as raised:
        dock_from_fields("home_dock", fields, "parameters")
    message = str(raised.value)
    assert message.startswith("parameters: dock 'home_dock'")
    assert field in message


def test_dock_file_errors_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(DockDatabaseError, match=r"missing.yaml: cannot read the dock database"):
        load_dock_file(tmp_path / "missing.yaml")
    no_docks = tmp_path / "no_docks.yaml"
    no_docks.write_text("stations: {}\n")
    with pytest.raises(DockDatabaseError, match=r"no_docks.yaml: the dock database does not contain 'docks'"):
        load_dock_file(no_docks)
    broken = tmp_path / "broken.yaml"
    broken.write_text("docks: [unclosed\n")
    with pytest.raises(DockDatabaseError, match=r"broken.yaml: the dock database is not valid YAML"):
        load_dock_file(broken)
    with pytest.raises(DockDatabaseError, match=r"f.yaml: dock 'a' must be a mapping"):
        docks_from_yaml({"docks": {"a": [1, 2]}}, "f.yaml")
    with pytest.raises(DockDatabaseError, match=r"f.yaml: dock 'b' has no 'type'"):
        docks_from_yaml({"docks": {"b": {"pose": [0, 0, 0]}}}, "f.yaml")


def test_lookups_by_name_and_type() -> None:
    home = Dock("home_dock", "simple_charging_dock", "map", Pose2D(0.0, 0.0, 0.0))
    odd = Dock("odd_dock", "nova_carter_dock", "map", Pose2D(1.0, 0.0, 0.0))
    database = DockDatabase({"simple_charging_dock": "plugin"}, {"home_dock": home, "odd_dock": odd})
    assert database.find_dock("home_dock") == (home, "plugin")
    with pytest.raises(DockNotInDB, match="dock 'nowhere' is not in the dock database") as raised:
        database.find_dock("nowhere")
    assert raised.value.code == DockErrorCode.DOCK_NOT_IN_DB
    with pytest.raises(DockNotValid, match="type 'nova_carter_dock'"):
        database.find_dock("odd_dock")
    assert database.find_plugin("") == "plugin"  # one plugin: an empty type means it
    assert database.find_plugin("other") is None
    two = DockDatabase({"a": 1, "b": 2})
    assert two.find_plugin("") is None and two.find_plugin("b") == 2
    database.reload({})
    with pytest.raises(DockNotInDB, match="known docks: none"):
        database.find_dock("home_dock")
