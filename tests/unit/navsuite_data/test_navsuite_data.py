"""navsuite_data: the shipped data is found through the package, and a user's path always wins.

The wheel test (tests/system/test_wheel_install.py) shows the lookups work in an installed wheel; these
pin the rules every command's file options rely on: a path that exists as given is the user's, a
relative ``config/``, ``maps/`` or ``sim2d/worlds/`` name that does not falls back to the shipped
file, and a missing file's message says where it was looked for.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import navsuite_data
from navsuite_data import config_path, data_dir, data_root, map_path, resolve, searched, shipped, world_path
from navsuite_testing.ros import REPO


def test_in_the_checkout_the_data_folders_are_the_repositorys_own() -> None:
    assert data_dir("config") == REPO / "config"
    assert data_dir("maps") == REPO / "maps"
    assert data_dir("worlds") == REPO / "sim2d" / "worlds"
    assert data_root() == REPO
    assert config_path("nav2_params.yaml").is_file()
    assert config_path("trees/navigate_to_pose_w_replanning_and_recovery.xml").is_file()
    assert map_path("turtlebot3_world.yaml").is_file()
    assert world_path("turtlebot3_world.yaml").is_file()
    with pytest.raises(ValueError, match=r"no data folder 'scripts' \(known: config, maps, worlds\)"):
        data_dir("scripts")


def test_every_data_folder_is_reached_through_the_package() -> None:
    """The package's folders link to the repository's: a wheel built from the checkout copies them."""
    package = Path(navsuite_data.__file__).parent
    for kind, folder in navsuite_data.SOURCE_FOLDERS.items():
        assert (package / kind).resolve() == REPO / folder


def test_repository_spelled_names_map_to_the_shipped_files() -> None:
    assert shipped("config/trees/x.xml") == data_dir("config") / "trees" / "x.xml"
    assert shipped("maps/office_small.yaml") == map_path("office_small.yaml")
    assert shipped("sim2d/worlds/empty.yaml") == world_path("empty.yaml")
    assert shipped("my_params.yaml") is None
    assert shipped("/etc/config/x.yaml") is None


def test_a_users_file_wins_over_the_shipped_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert resolve("config/nav2_params.yaml") == config_path("nav2_params.yaml")  # none here: shipped
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "nav2_params.yaml").write_text("mine")
    assert resolve("config/nav2_params.yaml") == Path("config/nav2_params.yaml")  # the user's, as given
    assert resolve(tmp_path / "elsewhere.yaml") == tmp_path / "elsewhere.yaml"  # absolute: as given


def test_a_missing_file_is_returned_as_given_and_the_message_says_where_it_looked(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert resolve("config/nope.yaml") == Path("config/nope.yaml")
    assert searched("config/nope.yaml") == (f"looked at {tmp_path / 'config' / 'nope.yaml'} and "
                                            f"{config_path('nope.yaml')}")
    assert searched("mine.yaml") == f"looked at {tmp_path / 'mine.yaml'}"
