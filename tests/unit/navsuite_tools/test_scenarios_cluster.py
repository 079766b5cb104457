"""The Ray backend's driver side without a cluster (the cluster runs in tests/system/
test_scenarios_ray.py): a task's artifacts unpacked where the farm keeps them, a re-queued outcome
marked, and ``--ray`` without Ray naming the extra that installs it."""

from __future__ import annotations

import json
import socket
import sys
from pathlib import Path

import pytest

from navsuite_tools.scenarios import main
from navsuite_tools.scenarios.cluster import INSTALL_HINT, describe, pack, receive, requeued, require_ray
from navsuite_tools.scenarios.verdict import Outcome

REPO = Path(__file__).resolve().parents[3]


def _node_run(node_dir: Path) -> Outcome:
    """What a task's run leaves on its node: a recording, a log, its outcome naming them there."""
    (node_dir / "logs").mkdir(parents=True)
    (node_dir / "run.mcap").write_bytes(b"\x89MCAP0\r\n" + bytes(range(256)) * 40)
    (node_dir / "logs" / "scenario-mission.log").write_text("goals: 1 of 1 reached; sim 3.10 s\n")
    outcome = Outcome("SUCCESS", "1 goals reached", sim_time=3.1,
                      artifacts={"mcap": str(node_dir / "run.mcap"), "logs": str(node_dir / "logs"),
                                 "elsewhere": "/data/shared/map.pgm"})
    (node_dir / "result.json").write_text(json.dumps(outcome.to_json()))
    return outcome


def test_the_artifacts_come_back_into_the_jobs_directory_with_paths_pointing_there(tmp_path: Path) -> None:
    node_dir, here = tmp_path / "node" / "navsuite-scenario-run-short_goal", tmp_path / "out" / "short_goal"
    outcome = _node_run(node_dir)
    reply = {"outcome": outcome.to_json(), "attempt": 1, "node_dir": str(node_dir), "archive": pack(node_dir)}

    got = receive(reply, here)

    assert (here / "run.mcap").read_bytes() == (node_dir / "run.mcap").read_bytes()
    assert (here / "logs" / "scenario-mission.log").read_text() == "goals: 1 of 1 reached; sim 3.10 s\n"
    assert got.artifacts == {"mcap": str(here / "run.mcap"), "logs": str(here / "logs"),
                             "elsewhere": "/data/shared/map.pgm"}
    assert (got.result, got.sim_time, got.attempts, got.detail) == ("SUCCESS", 3.1, 1, "1 goals reached")
    assert Outcome.from_json(json.loads((here / "result.json").read_text())) == got


def test_a_requeued_outcome_counts_its_attempts_and_says_so_in_its_detail() -> None:
    first = Outcome("SUCCESS", "1 goals reached")
    assert requeued(first, 1) == first
    again = requeued(first, 2)
    assert again.attempts == 2
    assert again.detail == "1 goals reached; re-queued: its worker died on attempt 1, this is attempt 2"
    assert requeued(Outcome("ERROR"), 2).detail.startswith("re-queued")
    assert "attempts: 2" in "\n".join(f"{k}: {v}" for k, v in again.to_json().items())  # JUnit's system-out


def test_a_tasks_error_is_described_by_its_cause() -> None:
    class TaskError(Exception):
        cause = TimeoutError("remote traceback ...\nno free ROS domain id in 51..100 for 600 s")

    assert describe(TaskError("ray::run_on_node() (pid=1)")) == \
        "TimeoutError: no free ROS domain id in 51..100 for 600 s"
    assert describe(ValueError()) == "ValueError"


def test_ray_missing_names_the_extra(monkeypatch: pytest.MonkeyPatch,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray raises ImportError
    with pytest.raises(RuntimeError, match=r"pip install navsuite\[cluster\]"):
        require_ray()
    code = main.main(["run", str(REPO / "config" / "scenarios" / "farm_selftest.yaml"), "-k", "short_goal",
                      "--ray", "auto", "--out", "unused"])
    assert code == main.EXIT_USAGE
    assert INSTALL_HINT in capsys.readouterr().err


def test_an_address_nobody_answers_at_fails_at_once_naming_it(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("ray", reason="the cluster extra is not installed")
    with socket.socket() as sock:  # a port just freed: nothing listens there
        sock.bind(("127.0.0.1", 0))
        address = f"127.0.0.1:{sock.getsockname()[1]}"
    code = main.main(["run", str(REPO / "config" / "scenarios" / "farm_selftest.yaml"), "-k", "short_goal",
                      "--ray", address, "--out", "unused"])
    assert code == main.EXIT_USAGE
    assert f"no Ray cluster answers at {address}" in capsys.readouterr().err
