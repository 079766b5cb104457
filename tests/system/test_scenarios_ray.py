"""The farm on a Ray cluster: a head and one worker node started on this machine (tests/helpers/
ray_cluster.py, one CPU each), ``navsuite-scenarios run --ray ADDRESS`` on two scenarios of
config/scenarios/farm_selftest.yaml (one passes, one is built to fail), compared with the local
backend's verdicts for them (tests/helpers/farm_selftest.py: tests/system/test_scenarios.py runs the
same scenarios on the local backend and holds it to the same table); then a runner whose Ray worker
dies (tests/helpers/scenario_ray_fakes.py), to see Ray re-queue the scenario once and the outcome say so.

Checks: equal verdicts, the artifacts (recording, report, logs) on the driver's side with the outcome's
paths pointing there, Ctrl-C (SIGINT to the command) stopping the scenarios running on the cluster, and
that neither the scenarios' processes (hence their DDS participants) nor the cluster's survive.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("ray", reason="the cluster extra is not installed (pip install navsuite[cluster])")

from navsuite_testing.ros import wait_until
from navsuite_tools.scenarios.executor import MARKER, processes_with_env
from tests.helpers.farm_selftest import SELFTEST, SELFTEST_VERDICTS
from tests.helpers.ray_cluster import TAG, local_cluster

pytestmark = [pytest.mark.slow, pytest.mark.ros]
REPO = Path(__file__).resolve().parents[2]
SUBSET = ["-k", "short_goal", "-k", "built_to_fail"]


@pytest.fixture(scope="module")
def cluster() -> Iterator[tuple[str, dict[str, str]]]:
    """The cluster's address and the environment its processes carry (for the drivers too)."""
    with local_cluster(dict(os.environ)) as started:
        yield started


def _scenario_processes(env: dict[str, str]) -> list[int]:
    """Live processes of scenarios this test ran: they carry the cluster's tag and a farm marker."""
    found = []
    for pid in processes_with_env(f"{TAG}={env[TAG]}"):
        try:
            environ = Path(f"/proc/{pid}/environ").read_bytes()
        except OSError:
            continue
        if f"\0{MARKER}=".encode() in b"\0" + environ:
            found.append(pid)
    return found


def _farm(out: Path, env: dict[str, str], *backend: str) -> dict[str, dict[str, object]]:
    run = subprocess.run([sys.executable, "-m", "navsuite_tools.scenarios.main", "run", str(SELFTEST),
                          *SUBSET, "--out", str(out), *backend],
                         cwd=REPO, env=env, capture_output=True, text=True, timeout=150)
    assert run.returncode == 1, run.stdout + run.stderr  # built_to_fail fails, on purpose
    return {name: json.loads((out / name / "result.json").read_text())
            for name in ("short_goal", "built_to_fail")}


@pytest.mark.timeout(330)
def test_a_ray_run_gives_the_local_verdicts_with_the_artifacts_back_here(
        cluster: tuple[str, dict[str, str]], tmp_path: Path) -> None:
    address, env = cluster
    remote = _farm(tmp_path / "ray", env, "--ray", address)
    verdicts = {name: (result["result"], result["result_code"]) for name, result in remote.items()}
    # the local backend's verdicts for these two (tests/system/test_scenarios.py checks a local run)
    assert verdicts == {name: SELFTEST_VERDICTS[name] for name in remote}
    assert verdicts == {"short_goal": ("SUCCESS", 0), "built_to_fail": ("ABORT", 208)}

    short = tmp_path / "ray" / "short_goal"
    assert remote["short_goal"]["artifacts"] == {"logs": str(short / "logs"), "mcap": str(short / "run.mcap"),
                                                 "report": str(short / "report.png")}
    assert (short / "run.mcap").stat().st_size > 0
    assert (short / "report.png").exists() and (short / "logs" / "scenario-mission.log").exists()
    assert remote["short_goal"]["attempts"] == 1
    assert 'src="short_goal/report.png"' in (tmp_path / "ray" / "summary.html").read_text()
    assert _scenario_processes(env) == []


@pytest.mark.timeout(120)
def test_a_scenario_whose_worker_dies_is_requeued_once_and_says_so(
        cluster: tuple[str, dict[str, str]], tmp_path: Path) -> None:
    from navsuite_tools.scenarios.cluster import RayExecutor
    from navsuite_tools.scenarios.farm import run_all, select
    from navsuite_tools.scenarios.schema import load_scenarios
    from tests.helpers.scenario_ray_fakes import dying_runner

    address, _env = cluster
    scenarios = select(load_scenarios(SELFTEST, REPO / "config"), ["short_goal", "built_to_fail"])
    executor = RayExecutor(address, (51, 100), runner=dying_runner)
    results = {r.scenario.name: r.outcome for r in run_all(scenarios, SELFTEST, tmp_path, executor)}
    assert results["short_goal"].result == "SUCCESS" and results["short_goal"].attempts == 2
    assert "re-queued" in results["short_goal"].detail
    assert (tmp_path / "short_goal" / "worker.log").read_text() == "second attempt\n"
    died = results["built_to_fail"]  # died on the retry too: fails alone, the farm goes on
    assert (died.result, died.attempts) == ("ERROR", 2) and "re-queued" in died.detail, died


@pytest.mark.timeout(120)
def test_ctrl_c_cancels_the_ray_run_and_stops_its_scenarios(
        cluster: tuple[str, dict[str, str]], tmp_path: Path) -> None:
    """Started with SIGINT ignored, as a non-interactive shell starts a background job (CI scripts
    do): the farm must still hear the interrupt. Before it set its own handler, Python kept the
    inherited SIG_IGN and both scenarios ran to the end (local CI runs CH and CI)."""
    address, env = cluster
    farm = subprocess.Popen([sys.executable, "-m", "navsuite_tools.scenarios.main", "run", str(SELFTEST),
                             *SUBSET, "--out", str(tmp_path), "--ray", address],
                            cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    try:
        wait_until(lambda: len(_scenario_processes(env)) >= 2, 60.0, "the scenarios' processes", step=0.5)
        farm.send_signal(signal.SIGINT)
        console, _ = farm.communicate(timeout=60)
    finally:
        farm.kill()
    assert farm.returncode == 130, console
    assert "interrupted; every scenario process was stopped" in console
    assert _scenario_processes(env) == []
    assert not (tmp_path / "short_goal" / "result.json").exists()  # cancelled: no result came back
