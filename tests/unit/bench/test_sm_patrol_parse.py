"""bench.bench_sm_patrol reads the demo's own lines: result, visiting order, sim time."""

from __future__ import annotations

from bench.bench_sm_patrol import parse_patrol, patrol_command

OUTPUT = """[patrol] [t=5.82 s] StiGoToLocation1 -> StiGoToLocation2 [NEXT] on EvCbSuccess[...]
[patrol] visited: location1 -> location2 -> station -> location3
[patrol] rounds 2, recharges 2, sim 98.1 s, wall 9.9 s
[patrol] result: SUCCESS
"""


def test_a_successful_run_is_read_from_its_lines() -> None:
    run = parse_patrol(OUTPUT, 12.5)
    assert run.succeeded and run.outcome == "SUCCESS"
    assert run.visited == "location1 -> location2 -> station -> location3"
    assert (run.sim_s, run.wall_s) == (98.1, 12.5)


def test_a_timeout_or_a_missing_result_line_is_a_failure() -> None:
    timeout = parse_patrol(OUTPUT.replace("SUCCESS", "TIMEOUT in ['SsPatrol', 'StiGoToLocation4']"), 240.0)
    assert not timeout.succeeded and timeout.outcome.startswith("TIMEOUT")
    assert not parse_patrol("[nav] [launch] shutting down\n", 3.0).succeeded


def test_the_command_is_the_system_tests() -> None:
    command = patrol_command("python")
    assert command[:3] == ["python", "-m", "smacc_py.state_machines.sm_battery_patrol.demo"]
    assert command[command.index("--low-threshold") + 1] == "0.95"
