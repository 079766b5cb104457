"""Mode states of sm_dance_bot, its global error event, and the superstate loop counter.

SMACC2: ``MsDanceBotRunMode`` (initial StAcquireSensors; ``EvGlobalError`` → MsDanceBotRecoveryMode) and
``MsDanceBotRecoveryMode`` (``EvGlobalError`` → ``deep_history<MsDanceBotRunMode::LastDeepState>``).
Upstream nothing posts EvGlobalError and the temperature alert has no transition. Here the run mode
runs ``CbConditionTemperatureSensor`` for its whole life, and its ``EvCustomTemperatureAlert`` enters
the recovery mode (tag OVERHEAT). The recovery mode stops the robot, switches the LED off and waits for a
reading at or below 38 °C (``CbTemperatureNormal``), then resumes the dance where it was interrupted
(deep history, tag RECOVERED). EvGlobalError keeps both of its upstream transitions.

Loop counters: SMACC2 keeps ``iteration_count`` in the superstate and increments it in the loop
condition. A superstate re-entered through deep history is a new instance, which would restart the
count, and a loop-start state re-entered through history would count an iteration twice. So
``LoopingSuperstate`` keeps the count of *started* iterations on the machine's blackboard
(``<Superstate>.iterations``), incremented by the loop start's CONTINUELOOP transition (its
``on_exit_CONTINUELOOP``), and records the final count in ``loops_completed`` when the loop ends.
"""

from __future__ import annotations

import logging
from typing import ClassVar

from smacc_py.clients.cl_nav2z import CbStopNavigation
from smacc_py.core import ABORT, SUCCESS, EvCbSuccess, History, SmaccEvent, SmaccState, Transition
from smacc_py.state_machines.sm_dance_bot.clients import (
    CbConditionTemperatureSensor,
    CbLEDOff,
    CbTemperatureNormal,
    EvCustomTemperatureAlert,
)
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation, OrTemperatureSensor
from smacc_py.state_machines.sm_dance_bot.sm_dance_bot import SmDanceBot

log = logging.getLogger("sm_dance_bot")

LOOPS_KEY = "loops_completed"  # global data: {superstate name: iterations completed}
RECOVERIES_KEY = "recoveries"  # global data: how many times the recovery mode was entered


class EvGlobalError(SmaccEvent):
    """A global error: run mode ↔ recovery mode (SMACC2: ``sm_dance_bot::EvGlobalError``)."""


class OVERHEAT(ABORT):
    """The temperature rose above the alert threshold: leave the run mode."""


class RECOVERED(SUCCESS):
    """The temperature is back to normal: resume where the run mode was interrupted."""


class MsDanceBotRunMode(SmaccState, parent=SmDanceBot):
    """The whole dance; over-temperature (or EvGlobalError) switches to the recovery mode."""

    inner_initial_state = "StAcquireSensors"
    reactions = [
        Transition(EvGlobalError, "MsDanceBotRecoveryMode"),
        Transition(EvCustomTemperatureAlert[CbConditionTemperatureSensor, OrTemperatureSensor],
                   "MsDanceBotRecoveryMode", OVERHEAT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTemperatureSensor, CbConditionTemperatureSensor)

    def on_exit_OVERHEAT(self) -> None:
        log.warning("over-temperature: entering the recovery mode")
        self.set_global_sm_data(RECOVERIES_KEY, self.get_global_sm_data(RECOVERIES_KEY, 0) + 1)


class MsDanceBotRecoveryMode(SmaccState, parent=SmDanceBot):
    """Stop, LED off, wait for a normal temperature, then resume the run mode's last state."""

    reactions = [
        Transition(EvCbSuccess[CbTemperatureNormal, OrTemperatureSensor], History(MsDanceBotRunMode),
                   RECOVERED),
        Transition(EvGlobalError, History(MsDanceBotRunMode)),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbStopNavigation)
        cls.configure_orthogonal(OrLED, CbLEDOff)
        cls.configure_orthogonal(OrTemperatureSensor, CbTemperatureNormal)

    def on_exit_RECOVERED(self) -> None:
        log.info("temperature normal: resuming the dance")


class StFinalState(SmaccState, parent=SmDanceBot):
    """The dance is over (new: upstream's last state returns to StNavigateToWaypointsX, whose waypoint
    list is exhausted by then)."""


class LoopingSuperstate(SmaccState):
    """A superstate whose inner states loop ``total_iterations`` times (completed iterations on the
    blackboard, so that deep history resumes the count)."""

    total_iterations: ClassVar[int] = 1

    @classmethod
    def counter_key(cls) -> str:
        """Blackboard key of the running count."""
        return f"{cls.__name__}.iterations"

    def completed(self) -> int:
        """Iterations started so far (the running one included)."""
        count: int = self.get_global_sm_data(self.counter_key(), 0)
        return count

    def count_iteration(self) -> None:
        """One more iteration started."""
        self.set_global_sm_data(self.counter_key(), self.completed() + 1)
        log.info("%s: iteration %d/%d", type(self).__name__, self.completed(), self.total_iterations)

    def loop_condition(self) -> bool:
        """True while iterations remain (SMACC2's loopWhileCondition)."""
        return self.completed() < self.total_iterations

    def on_exit_ENDLOOP(self) -> None:
        done = dict(self.get_global_sm_data(LOOPS_KEY, {}))
        done[type(self).__name__] = self.completed()
        self.set_global_sm_data(LOOPS_KEY, done)
        self.set_global_sm_data(self.counter_key(), 0)


class LoopStartState(SmaccState):
    """Base of the loop-start inner states (SMACC2's StiRadialLoopStart, StiSPatternLoopStart,
    StiFPatternStartLoop): on entry posts ``EvLoopContinue`` or ``EvLoopEnd`` for this state; taking
    the CONTINUELOOP transition starts an iteration of ``superstate``."""

    superstate: ClassVar[type[LoopingSuperstate]]

    def on_entry(self) -> None:
        ss = self.context(self.superstate)
        log.info("%s: iterations started %d/%d", type(ss).__name__, ss.completed(), ss.total_iterations)
        self.check_while_loop_condition_and_throw_event(ss.loop_condition)

    def on_exit_CONTINUELOOP(self) -> None:
        self.context(self.superstate).count_iteration()
