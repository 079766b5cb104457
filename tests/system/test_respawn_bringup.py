"""nav-bringup's respawn (issue 45), as nav2_bringup's ``use_respawn``: which processes it restarts.

The node processes respawn (on by default, ``--no-respawn`` turns it off), the initial-pose publisher
then stays up to give a restarted AMCL its last pose, and the simulator never respawns: its death
ends the launch with a line naming it. The end-to-end run (a killed navigation process, respawned,
and the mission completed) is tests/system/test_scenarios.py's goals_navigation_killed.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.ros.bringup import nav_bringup as bringup
from ros_tools.launch import Launcher, ProcessSpec
from tests.helpers.fake_processes import dying


@pytest.fixture(autouse=True)
def _default_layout(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(bringup.LAYOUT_ENV, raising=False)


def _specs(*argv: str) -> dict[str, ProcessSpec]:
    return {spec.name: spec for spec in bringup.process_specs(bringup.parse_args(argv))}


@pytest.mark.parametrize("argv, nodes", [((), ["nav2"]), (("--isolated",), ["localization", "navigation"])])
def test_node_processes_respawn_by_default_and_the_simulator_never(argv: tuple[str, ...],
                                                                   nodes: list[str]) -> None:
    specs = _specs(*argv)
    assert [name for name, spec in specs.items() if spec.respawn] == nodes
    assert all(specs[name].respawn_delay == bringup.RESPAWN_DELAY for name in nodes)
    assert not specs["sim2d"].respawn and not specs["initial_pose"].respawn
    assert "resend_after_restart:=true" in specs["initial_pose"].cmd


def test_no_respawn_turns_it_off() -> None:
    specs = _specs("--no-respawn", "--isolated")
    assert not any(spec.respawn for spec in specs.values())
    assert "resend_after_restart:=false" in specs["initial_pose"].cmd


def test_a_dead_simulator_is_named_with_the_reason_it_is_not_respawned(tmp_path: Path) -> None:
    lines: list[str] = []
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    launcher.start([ProcessSpec("sim2d", dying(tmp_path / "sim", [247]), ready="ready")])
    assert launcher.wait() == 247
    bringup._name_a_dead_simulator(launcher)
    launcher.shutdown()
    assert f"[launch] ERROR: sim2d died: {bringup.SIM_NOT_RESPAWNED}; ending the run" in lines
