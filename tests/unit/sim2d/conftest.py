"""Shared fixtures for sim2d unit tests: the TurtleBot3 world and a simulator factory."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from sim2d.core.robot import WAFFLE, Pose2D, RobotModel
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import World, load_world, parse_world

SPAWN = Pose2D(-2.0, -0.5, 0.0)


@pytest.fixture(scope="session")
def tb3_world() -> World:
    return load_world("turtlebot3_world")


@pytest.fixture
def make_sim(tb3_world: World) -> Callable[..., Simulator]:
    """Simulator at ``pose`` (default: the TB3 spawn) with ``seed`` and component overrides."""

    def factory(pose: Pose2D = SPAWN, seed: int = 0, robot: RobotModel = WAFFLE,
                physics_step: float = 0.005, **components: Any) -> Simulator:
        params = SimParams(physics_step=physics_step, initial_pose=pose)
        return Simulator(tb3_world, robot, params, np.random.default_rng(seed), **components)

    return factory


def drive(sim: Simulator, v: float, w: float, seconds: float) -> None:
    """Command (v, w) every step for ``seconds`` of sim time."""
    for _ in range(round(seconds / sim.params.physics_step)):
        sim.command(v, w)
        sim.step()


def room_with_docks(*docks: dict[str, Any], half: float = 2.0) -> World:
    """A square room (inner half-size ``half`` m, walls 0.1 m) holding ``docks`` (world YAML entries)."""
    inner = [[-half, -half], [half, -half], [half, half], [-half, half]]
    data = {"name": "dock_room", "obstacles": [{"type": "ring", "vertices": inner, "thickness": 0.1}],
            "docks": list(docks)}
    return parse_world(data, Path("dock_room.yaml"))


def sim_in(world: World, pose: Pose2D, robot: RobotModel = WAFFLE, seed: int = 0,
           **components: Any) -> Simulator:
    """A simulator in ``world`` with the robot at ``pose``."""
    return Simulator(world, robot, SimParams(initial_pose=pose), np.random.default_rng(seed), **components)
