"""The seed project's battery-patrol tree (v3 original and v4 port) with fake nodes reproduces
the seed's behaviour: location1..4, root FAILURE, then station, wait, recharge, root SUCCESS, again."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.bt import BehaviorTreeFactory, NodeStatus
from tests.helpers.bt_seed_fakes import SeedWorld, register_seed_fakes

TREES = Path(__file__).resolve().parents[3] / "config" / "trees"
TICK_PERIOD = 0.5  # s, the seed's wall timer
ONE_CYCLE = ["location1", "location2", "location3", "location4", "FAILURE",
             "station", "wait", "recharge", "SUCCESS"]


@pytest.mark.parametrize("file_name", ["seed_battery_patrol_v3.xml", "seed_battery_patrol_v4.xml"])
def test_seed_tree_patrols_then_recharges_over_two_cycles(file_name: str) -> None:
    world = SeedWorld()
    factory = BehaviorTreeFactory()
    register_seed_fakes(factory, world)
    tree = factory.create_tree_from_file(TREES / file_name)
    battery_at_root_result = []
    wait_started = wait_ended = 0.0
    for k in range(1000):
        now = k * TICK_PERIOD
        status = tree.tick_once(now)
        if world.log and world.log[-1] == "wait" and not wait_started:
            wait_started = now
        if status.is_completed:
            if status is NodeStatus.SUCCESS and not wait_ended:
                wait_ended = now
            world.log.append(status.value)
            battery_at_root_result.append(world.battery)
        if world.log.count("SUCCESS") == 2:
            break
    assert world.log == ONE_CYCLE + ONE_CYCLE
    assert battery_at_root_result == [0, 100, 0, 100]
    assert wait_ended - wait_started >= 30.0  # the recharge wait lasted 30 s of tree time


def test_seed_tree_goto_is_halted_when_the_tree_is_halted() -> None:
    world = SeedWorld(travel_ticks=10)
    factory = BehaviorTreeFactory()
    register_seed_fakes(factory, world)
    tree = factory.create_tree_from_file(TREES / "seed_battery_patrol_v3.xml")
    for k in range(3):
        assert tree.tick_once(k * TICK_PERIOD) is NodeStatus.RUNNING
    tree.halt()
    assert world.log == ["halted:location1"]
