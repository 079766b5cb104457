"""A nav-bringup component that is not ready says what it waits for (issue 41: never a silent wait)."""

from __future__ import annotations

from dataclasses import dataclass

from nav_stack.ros.bringup.bringup_components import waiting_for


@dataclass
class FakeManager:
    name: str
    step: str
    system_active: bool = False

    def get_name(self) -> str:
        return self.name


@dataclass
class FakeCostmap:
    name: str
    has_map: bool

    def get_name(self) -> str:
        return self.name

    def resolve_topic_name(self, topic: str) -> str:
        return f"/{topic}"


def test_each_missing_piece_is_named() -> None:
    managers = [FakeManager("lifecycle_manager_localization", "configuring amcl"),
                FakeManager("lifecycle_manager_navigation", "active", system_active=True)]
    costmaps = [FakeCostmap("global_costmap", has_map=False), FakeCostmap("local_costmap", has_map=True)]
    assert waiting_for(managers, costmaps, clock_heard=False, map_needed=True) == [
        "/clock (no message yet: is the simulator running?)",
        "lifecycle_manager_localization: configuring amcl",
        "global_costmap: the map on /map",
    ]


def test_nothing_is_named_once_everything_is_there() -> None:
    managers = [FakeManager("lifecycle_manager_navigation", "active", system_active=True)]
    costmaps = [FakeCostmap("global_costmap", has_map=False)]
    assert waiting_for(managers, costmaps, clock_heard=True, map_needed=False) == []
