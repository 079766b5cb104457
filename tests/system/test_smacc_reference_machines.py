"""SMACC2's reference machines, ported, on the ROS graph: each runs under ``smacc-run <name>`` on sim time,
and the transitions it reports on its introspection topic (``/<SmName>/smacc/transition_log``) must be
those of the upstream machine's definition.

The expected sequences are written out here from the upstream headers (each test names its files), not
taken from the ports. The test drives /clock with ``smacc_py.ros.sim_clock.SimClockLeader``: the
machine's minutes of timers pass in a few wall seconds, every /clock step reaches it (lockstep), and
between steps the test can press keys or call services at a sim time of its choosing.
"""

from __future__ import annotations

import itertools
import signal
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import SmaccTransitionLogEntry

from navsuite_testing.ros import spin_until
from smacc_py.ros.sim_clock import SimClockLeader

pytestmark = [pytest.mark.slow, pytest.mark.ros]

#: The transition log's QoS (smacc_py/ros/introspection.py): a late subscriber still gets the entries.
LOG = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.TRANSIENT_LOCAL)
WALL_S = 60.0  # wall s any one wait may take on a loaded machine (a run takes a few)

Key = tuple[str, str, str]  # (source, target, tag)


def _command(script: str, module: str) -> list[str]:
    """The console script of this environment, or ``python -m`` its module before a reinstall made it."""
    exe = Path(sys.executable).parent / script
    return [str(exe)] if exe.exists() else [sys.executable, "-m", module]


def _run(cmd: list[str]) -> str:
    """Run a command line as a user would (docs/smacc2-guide.md's), asserting exit status 0; its output."""
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=WALL_S)
    assert done.returncode == 0, f"{cmd}: {done.stdout}{done.stderr}"
    return done.stdout


class MachineOnGraph:
    """``smacc-run <machine>`` on sim time, a probe node hearing its transition log, and the /clock."""

    def __init__(self, ros_context: Any, machine: str, sm_name: str, step_s: float) -> None:
        self.node = rclpy.create_node("reference_machine_probe", context=ros_context)
        self.executor = SingleThreadedExecutor(context=ros_context)
        self.executor.add_node(self.node)
        self.log: list[SmaccTransitionLogEntry] = []
        self.node.create_subscription(SmaccTransitionLogEntry, f"/{sm_name}/smacc/transition_log",
                                      self.log.append, LOG)
        self.clock = SimClockLeader(self.node, sm_name, step_s=step_s)
        # As docs/smacc2-guide.md says, on the default executor (a /clock that stands still between steps
        # once stalled rclpy's EventsExecutor; sim-time timers are now called by the clock).
        command = [*_command("smacc-run", "smacc_py.ros.runner"), machine,
                   "--ros-args", "-p", "use_sim_time:=true"]
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)

    def transitions(self) -> list[Key]:
        return [(e.transition.source_state_name, e.transition.destiny_state_name,
                 e.transition.transition_type) for e in self.log]

    def run_until(self, predicate: Callable[[], bool], what: str) -> None:
        """Advance sim time until ``predicate()``."""
        if not self.clock.run(self.executor, predicate, WALL_S):
            raise AssertionError(f"no {what} within {WALL_S} s wall ({self.clock.elapsed_s:.1f} s sim); "
                                 f"transitions: {self.transitions()}")

    def wait(self, predicate: Callable[[], bool], what: str) -> None:
        """Spin without advancing sim time until ``predicate()``."""
        spin_until(self.executor, predicate, WALL_S, what)

    def count(self, n: int) -> Callable[[], bool]:
        return lambda: len(self.log) >= n

    def stop(self) -> str:
        """Ctrl-C the machine; its output (exit status 0 and no traceback asserted)."""
        self.process.send_signal(signal.SIGINT)
        status = self.process.wait(timeout=30)
        out = self.process.stdout.read() if self.process.stdout else ""
        assert status == 0 and "Traceback" not in out, out
        return out

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.clock.destroy()
        self.executor.shutdown()
        self.node.destroy_node()


@pytest.fixture
def on_graph(ros_context: Any) -> Iterator[Callable[[str, str, float], MachineOnGraph]]:
    runs: list[MachineOnGraph] = []

    def start(machine: str, sm_name: str, step_s: float = 0.05) -> MachineOnGraph:
        runs.append(MachineOnGraph(ros_context, machine, sm_name, step_s))
        return runs[-1]

    yield start
    for run in runs:
        run.close()


def _intervals(log: list[SmaccTransitionLogEntry]) -> list[float]:
    """Sim s between successive transitions (the log's stamps are the machine's node clock)."""
    stamps = [entry.timestamp.sec + entry.timestamp.nanosec * 1e-9 for entry in log]
    return [b - a for a, b in itertools.pairwise(stamps)]


def _countdowns_hold(intervals: list[float], nominal_s: float) -> bool:
    """Each countdown took its ticks: never less than ``nominal_s`` (0.1 s for float stamps), at most 10 %
    more. Why a margin: the lockstep report goes out from the /clock callback, before the timers that
    /clock made due have run, so on a loaded machine a tick may land a step late (seen: 500.5 s with the
    SingleThreadedExecutor and 502 s with the EventsExecutor, for 500 ticks of 1 s, both cores busy)."""
    return all(nominal_s - 0.1 <= interval <= 1.1 * nominal_s for interval in intervals)


@pytest.mark.timeout(120)
def test_sm_atomic_alternates_every_five_ticks(on_graph: Callable[..., MachineOnGraph]) -> None:
    # smacc2_sm_reference_library/sm_atomic: orthogonals/or_timer.hpp (ClRos2Timer, 1 s),
    # states/st_state_1.hpp (CbTimerCountdownOnce(5): EvTimer -> State2, SUCCESS; a
    # CbTimerCountdownLoop(3) whose events go unhandled), states/st_state_2.hpp (-> State1, SUCCESS).
    expected = [("State1", "State2", "SUCCESS"), ("State2", "State1", "SUCCESS")] * 2
    run = on_graph("sm_atomic", "SmAtomic")
    run.run_until(run.count(4), "four transitions")
    assert run.transitions()[:4] == expected
    assert _countdowns_hold(_intervals(run.log[:4]), 5.0), _intervals(run.log[:4])  # 5 ticks of 1 s
    assert "Entering State2" in run.stop()


@pytest.mark.timeout(120)
def test_sm_atomic_24hr_first_transitions(on_graph: Callable[..., MachineOnGraph]) -> None:
    # smacc2_sm_reference_library/sm_atomic_24hr: orthogonals/or_timer.hpp (cl_ros_timer::ClRosTimer,
    # 1 s), states/st_state_1.hpp and st_state_2.hpp (CbTimerCountdownOnce(500): EvTimer -> the other
    # state, SUCCESS). The day-long run is bench/bench_sm_atomic_24hr.py. Steps of 0.5 s: the machine's
    # only timer ticks every 1 s, so none of its ticks is skipped.
    expected = [("State1", "State2", "SUCCESS"), ("State2", "State1", "SUCCESS"),
                ("State1", "State2", "SUCCESS")]
    run = on_graph("sm_atomic_24hr", "SmAtomic24Hr", 0.5)
    run.run_until(run.count(3), "three transitions")
    assert run.transitions()[:3] == expected
    assert _countdowns_hold(_intervals(run.log[:3]), 500.0), _intervals(run.log[:3])  # 500 ticks of 1 s
    run.stop()


def _loop(superstate: str) -> list[Key]:
    """sm_three_some's superstates/ss_superstate_{1,2}.hpp (total_iterations 5) and
    states/inner_states/sti_state_{1,2,3}.hpp: StiState1 -> StiState2 on EvLoopContinue (CONTINUELOOP),
    StiState2 -> StiState3 and StiState3 -> StiState1 on their countdowns (TIMEOUT)."""
    names = [f"{superstate}StiState{i}" for i in (1, 2, 3)]
    return [(names[0], names[1], "CONTINUELOOP"), (names[1], names[2], "TIMEOUT"),
            (names[2], names[0], "TIMEOUT")] * 5


@pytest.mark.timeout(150)
def test_sm_three_some_keys_reactor_loops_and_final_state(on_graph: Callable[..., MachineOnGraph]) -> None:
    # smacc2_sm_reference_library/sm_three_some: mode_states/ms_run.hpp (initial StState1),
    # states/st_state_1.hpp (EvTimer -> StState2 TIMEOUT), st_state_2.hpp (EvAllGo<SrAllEventsGo> of the
    # keys A, B and C -> StState3, untagged; EvKeyPressP -> StState1 PREVIOUS), st_state_3.hpp
    # (EvKeyPressP -> StState2 PREVIOUS; EvTimer -> Ss1 TIMEOUT), the superstates (EvLoopEnd ->
    # Ss2, then StState4) and st_state_4.hpp (its table is named `transitions`: no reactions, it stays).
    # Untagged transitions take their event's default tag: SUCCESS for EvAllGo, ENDLOOP for EvLoopEnd.
    run = on_graph("sm_three_some", "SmThreeSome")
    run.run_until(run.count(1), "the first countdown")
    # The clock now stands still (one step past the transition, well inside StState2's 5 s countdown):
    # the keys decide, pressed as the README says.
    for key in "abc":
        _run([*_command("smacc-key", "smacc_py.clients.cl_keyboard.send_key"), key])
    run.wait(run.count(2), "SrAllEventsGo's EvAllGo")
    _run([*_command("smacc-key", "smacc_py.clients.cl_keyboard.send_key"), "p"])
    run.wait(run.count(3), "the key p")
    expected = [("StState1", "StState2", "TIMEOUT"), ("StState2", "StState3", "SUCCESS"),
                ("StState3", "StState2", "PREVIOUS"), ("StState2", "StState3", "TIMEOUT"),
                ("StState3", "Ss1", "TIMEOUT"), *_loop("Ss1"), ("Ss1", "Ss2", "ENDLOOP"), *_loop("Ss2"),
                ("Ss2", "StState4", "ENDLOOP")]
    run.run_until(run.count(len(expected)), "StState4")
    final_s = run.clock.now_s
    run.run_until(lambda: run.clock.now_s > final_s + 10.0, "10 s in StState4")  # two countdowns' worth
    assert run.transitions() == expected


@pytest.mark.timeout(120)
def test_sm_atomic_services_returns_on_each_service_call(on_graph: Callable[..., MachineOnGraph]) -> None:
    # smacc2_sm_reference_library/sm_atomic_services: states/st_state_1.hpp (CbTimerCountdownOnce(5) on a
    # 1 s ClRosTimer -> State2, SUCCESS), states/st_state_2.hpp (EvServiceRequestReceieved<CbServiceServer,
    # OrServices> -> State1, SUCCESS), orthogonals/or_services.hpp (serves and calls "service", Empty).
    run = on_graph("sm_atomic_services", "SmAtomicServices")
    call = [*_command("ros2py", "navsuite_tools.cli.main"), "service", "call", "/service",
            "std_srvs/srv/Empty"]
    for cycle in range(2):
        run.run_until(run.count(2 * cycle + 1), "State1's countdown")
        on_entry = run.clock.now_s
        run.run_until(lambda start=on_entry: run.clock.now_s > start + 20.0,  # type: ignore[misc]
                      "20 s in State2")
        assert len(run.log) == 2 * cycle + 1  # no timeout: only a call leaves State2
        assert "response:" in _run(call)  # as the README says; the answer comes from the machine
        run.wait(run.count(2 * cycle + 2), "the transition back to State1")
    assert run.transitions() == [("State1", "State2", "SUCCESS"), ("State2", "State1", "SUCCESS")] * 2
    assert [e.transition.event.event_source for e in run.log[1::2]] == ["CbServiceServer"] * 2
    run.stop()
