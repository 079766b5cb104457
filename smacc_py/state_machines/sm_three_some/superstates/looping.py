"""What Ss1 and Ss2 share: a superstate counting its iterations, and its three inner states.

Upstream includes the same three inner-state headers (``states/inner_states/sti_state_*.hpp``) in the
namespaces of both superstates, so each superstate gets its own ``StiState1..3``. Here
``declare_inner_states`` declares them once per superstate, named after it (``Ss1StiState1``): names
are how transitions and introspection tell states apart.

* ``StiState1``: on entry, another iteration (EvLoopContinue → StiState2, CONTINUELOOP) while the
  superstate's ``iteration_count`` (then incremented) is under ``total_iterations``, else EvLoopEnd,
  on which the superstate leaves;
* ``StiState2``: StiState3 on its countdown (TIMEOUT) or ``n``; StiState1 on ``p``;
* ``StiState3``: StiState1 on its countdown (TIMEOUT) or ``n``; StiState2 on ``p``.
"""

from __future__ import annotations

from typing import Any, ClassVar

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import (
    CONTINUELOOP,
    EvKeyPressN,
    EvKeyPressP,
    EvLoopContinue,
    EvTimer,
    SmaccState,
    Transition,
)
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrTimer
from smacc_py.state_machines.sm_three_some.states.common import (
    LoggedState,
    configure_timeout_keys_and_sensor,
)
from smacc_py.state_machines.sm_three_some.tags import NEXT, PREVIOUS, TIMEOUT


class LoopingSuperstate(SmaccState):
    """A superstate whose first inner state loops ``total_iterations`` times; the count lives as long as
    the superstate is active (upstream's ``int iteration_count = 0`` member)."""

    total_iterations: ClassVar[int] = 5
    iteration_count: int = 0


class LoopStart(LoggedState):
    """StiState1: decides, on entry, between another iteration and the end of the loop."""

    def loop_while_condition(self) -> bool:
        """Upstream's ``loopWhileCondition``: ``iteration_count++ < total_iterations()``."""
        superstate = self.parent
        assert isinstance(superstate, LoopingSuperstate)
        self.getLogger().info(f"Loop start, current iterations: {superstate.iteration_count}, total "
                              f"iterations: {superstate.total_iterations}")
        running = superstate.iteration_count < superstate.total_iterations
        superstate.iteration_count += 1
        return running

    def on_entry(self) -> None:
        self.getLogger().info("LOOP START ON ENTRY")
        self.check_while_loop_condition_and_throw_event(self.loop_while_condition)


class TimedStep(LoggedState):
    """StiState2 and StiState3: the common countdown, sensor and keyboard behaviors."""

    @classmethod
    def static_configure(cls) -> None:
        configure_timeout_keys_and_sensor(cls)


def declare_inner_states(superstate: str, module: str) -> tuple[type[SmaccState], ...]:
    """StiState1..3 of ``superstate`` (a name), declared as if written in ``module`` (the caller's
    ``__name__``), named ``<superstate>StiState<i>``."""
    first, second, third = (f"{superstate}StiState{i}" for i in (1, 2, 3))
    timer = EvTimer[CbTimerCountdownOnce, OrTimer]  # type: ignore[type-arg]
    key_n = EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard]
    key_p = EvKeyPressP[CbDefaultKeyboardBehavior, OrKeyboard]
    declarations: list[tuple[str, type[SmaccState], list[Transition], str]] = [
        (first, LoopStart, [Transition(EvLoopContinue[first], second, CONTINUELOOP)],
         f"{superstate}'s loop start: another iteration or the end of the loop."),
        (second, TimedStep, [Transition(timer, third, TIMEOUT), Transition(key_n, third, NEXT),
                             Transition(key_p, first, PREVIOUS)],
         f"{superstate}'s second step: {third} on its countdown or n, {first} on p."),
        (third, TimedStep, [Transition(timer, first, TIMEOUT), Transition(key_p, second, PREVIOUS),
                            Transition(key_n, first, NEXT)],
         f"{superstate}'s third step: {first} on its countdown or n, {second} on p."),
    ]
    states = []
    for name, base, reactions, doc in declarations:
        namespace: dict[str, Any] = {"reactions": reactions, "__module__": module, "__doc__": doc,
                                     "__qualname__": name}
        states.append(type(name, (base,), namespace, parent=superstate))
    return tuple(states)
