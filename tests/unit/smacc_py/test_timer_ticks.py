"""SMACC2's timer semantics: the client ticks every ``duration``; countdowns count ticks (int); CbTimer
posts each tick. A float countdown counts seconds on its own timer. An integer countdown on a client
without a tick period is refused at startup with what SMACC2's call means. Time is the harness's
manual machine clock, so the instants below are exact."""

from __future__ import annotations

from datetime import timedelta
from typing import Any

import pytest

from smacc_py.clients.cl_ros2_timer import CbTimer, CbTimerCountdownLoop, CbTimerCountdownOnce, ClRos2Timer
from smacc_py.clients.cl_ros_timer import ClRosTimer
from smacc_py.core import (
    EvTimer,
    InvalidDefinitionError,
    Orthogonal,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.testing import MachineHarness


class Timers(SmaccObserver):
    """Machine-clock instant of every EvTimer, by event class name."""

    def __init__(self) -> None:
        self.at: dict[str, list[float]] = {}

    def on_event_posted(self, sm: Any, event: Any) -> None:
        if isinstance(event, EvTimer):
            self.at.setdefault(type(event).__name__, []).append(round(sm.now(), 6))


def machine(client: type, client_args: tuple[Any, ...], behavior: type,
            *args: Any) -> type[SmaccStateMachineBase]:
    """One state running ``behavior(*args)`` on an orthogonal holding ``client(*client_args)``; its first
    EvTimer[behavior] leaves for StDone."""

    class OrTimer(Orthogonal):
        def on_initialize(self) -> None:
            self.create_client(client, *client_args)

    class StCount(SmaccState, parent="SmTimer"):
        reactions = (Transition(EvTimer[behavior, OrTimer], "StDone"),)

        @classmethod
        def static_configure(cls) -> None:
            cls.configure_orthogonal(OrTimer, behavior, *args)

    class StDone(SmaccState, parent="SmTimer"):
        pass

    class SmTimer(SmaccStateMachineBase):
        initial_state = StCount

        def on_initialize(self) -> None:
            self.create_orthogonal(OrTimer)

    return SmTimer


def run(sm_type: type[SmaccStateMachineBase], seconds: float) -> tuple[MachineHarness[Any], Timers]:
    harness = MachineHarness(sm_type)
    timers = Timers()
    harness.sm.add_observer(timers)
    harness.start()
    harness.advance(seconds)
    harness.close()
    return harness, timers


def test_a_countdown_of_n_ticks_waits_n_periods_of_the_client_not_n_seconds() -> None:
    harness, timers = run(machine(ClRos2Timer, (0.5,), CbTimerCountdownOnce, 4), 5.0)
    assert timers.at["EvTimer[CbTimerCountdownOnce, OrTimer]"] == [2.0]  # 4 ticks x 0.5 s
    assert harness.transitions() == [("StCount", "StDone", "DEFAULT")]
    # the client itself posts every tick, as SMACC2's (EvTimer<ClRos2Timer, Or>)
    assert timers.at["EvTimer[ClRos2Timer, OrTimer]"] == [0.5 * k for k in range(1, 11)]


def test_a_loop_countdown_fires_every_n_ticks_and_cb_timer_every_tick() -> None:
    _, timers = run(machine(ClRos2Timer, (timedelta(milliseconds=250),), CbTimerCountdownLoop, 3), 2.0)
    assert timers.at["EvTimer[CbTimerCountdownLoop, OrTimer]"] == [0.75]  # then StDone: the loop ends
    _, timers = run(machine(ClRos2Timer, (0.5,), CbTimer), 1.0)
    assert timers.at["EvTimer[CbTimer, OrTimer]"] == [0.5]


def test_cl_ros_timer_is_smacc2s_humble_client_with_the_same_ticks() -> None:
    _, timers = run(machine(ClRosTimer, (0.5,), CbTimerCountdownOnce, 40), 25.0)
    assert timers.at["EvTimer[CbTimerCountdownOnce, OrTimer]"] == [20.0]  # the literal port: 40 ticks
    with pytest.raises(TypeError, match=r"ClRosTimer\(duration, oneshot=False\): the tick period is"):
        ClRosTimer(None)


def test_a_oneshot_client_ticks_once() -> None:
    _, timers = run(machine(ClRos2Timer, (0.5, True), CbTimerCountdownOnce, 2), 3.0)
    assert timers.at["EvTimer[ClRos2Timer, OrTimer]"] == [0.5]
    assert "EvTimer[CbTimerCountdownOnce, OrTimer]" not in timers.at  # a second tick never comes


def test_a_float_countdown_counts_seconds_and_needs_no_tick_period() -> None:
    harness, timers = run(machine(ClRos2Timer, (), CbTimerCountdownOnce, 1.5), 3.0)
    assert timers.at == {"EvTimer[CbTimerCountdownOnce, OrTimer]": [1.5]}
    assert harness.transitions() == [("StCount", "StDone", "DEFAULT")]


@pytest.mark.parametrize(("behavior", "args", "says"), [
    (CbTimerCountdownOnce, (40,),
     r"StCount: CbTimerCountdownOnce on OrTimer: CbTimerCountdownOnce\(40\) counts 40 ticks of the "
     r"orthogonal's ClRos2Timer, as in SMACC2, but that client has no tick period: create it with one "
     r"\(create_client\(ClRos2Timer, 0.5\) ticks every 0.5 s\), or count seconds with a float "
     r"\(CbTimerCountdownOnce\(40.0\)\)"),
    (CbTimer, (), r"StCount: CbTimer on OrTimer: CbTimer\(\) counts every tick of the orthogonal's "
                  r"ClRos2Timer, as in SMACC2, but that client has no tick period"),
])
def test_a_tick_count_without_a_tick_period_is_refused_at_startup(behavior: type, args: tuple[Any, ...],
                                                                  says: str) -> None:
    sm_type = machine(ClRos2Timer, (), behavior, *args)
    with pytest.raises(InvalidDefinitionError, match=says):
        sm_type().start()


@pytest.mark.parametrize(("build", "says"), [
    (lambda: CbTimerCountdownOnce(0), r"CbTimerCountdownOnce: the tick count must be >= 1, got 0"),
    (lambda: CbTimerCountdownLoop(True), r"expected a tick count \(int\) or a duration in seconds \(float\)"),
    (lambda: CbTimerCountdownOnce(-1.0), r"the duration must be > 0 s and finite, got -1.0"),
    (lambda: ClRos2Timer("1s"), r"ClRos2Timer: a duration is seconds, a timedelta or an rclpy Duration"),
])
def test_bad_timer_arguments_fail_at_construction(build: Any, says: str) -> None:
    with pytest.raises((TypeError, ValueError), match=says):
        build()
