"""The skeleton shared by sm_dance_bot's looping superstates (radial, F and S patterns), declared once.

Each pattern is a ``LoopingSuperstate`` whose inner loop is a loop-start state (``EvLoopContinue`` →
the first motion, CONTINUELOOP; the superstate leaves on ``EvLoopEnd`` with ENDLOOP) followed by
motion states. Every motion state runs one cl_nav2z behavior on OrNavigation and one LED behavior on
OrLED, goes to its successor on the behavior's ``EvCbSuccess`` (SUCCESS) and on its ``EvCbFailure``
(ABORT) to ``on_failure``, by default the successor too: a motion the behavior server refuses costs one
leg of the figure, never the machine. So a pattern module states only what differs: names, motions,
distances, LED and where each state goes.

States are built with ``type(...)`` under the caller's module name, as if written there: the model
resolves state names given as strings in the module of the state that names them.
"""

from __future__ import annotations

from typing import Any

from smacc_py.clients.cl_nav2z import CbNavigateForward
from smacc_py.core import (
    ABORT,
    CONTINUELOOP,
    ENDLOOP,
    SUCCESS,
    EvCbFailure,
    EvCbSuccess,
    EvLoopContinue,
    EvLoopEnd,
    ISmaccClientBehavior,
    SmaccState,
    Transition,
)
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.modestates import LoopingSuperstate, LoopStartState
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation


def loop_end(loop_start: str, following: str) -> list[Transition]:
    """A looping superstate's reactions: leave for ``following`` once ``loop_start`` ends the loop."""
    return [Transition(EvLoopEnd[loop_start], following, ENDLOOP)]


class LoopPattern:
    """Declares the inner states of one looping superstate, in ``module`` (the caller's ``__name__``)."""

    def __init__(self, superstate: type[LoopingSuperstate], module: str) -> None:
        self.superstate, self.module = superstate, module

    def loop_start(self, name: str, first: str, doc: str) -> type[SmaccState]:
        """The loop-start state: another iteration from ``first``, or the end of the loop."""
        reactions = [Transition(EvLoopContinue[name], first, CONTINUELOOP)]
        return self._declare(name, LoopStartState, reactions, (), doc)

    def motion(self, name: str, behavior: type[ISmaccClientBehavior], *args: Any,
               led: type[ISmaccClientBehavior], following: str, on_failure: str | None = None,
               base: type[SmaccState] = SmaccState, doc: str | None = None) -> type[SmaccState]:
        """A state running ``behavior(*args)`` and ``led``; then ``following`` (``on_failure`` if it fails).

        ``base`` adds behavior of its own (e.g. a ``runtime_configure``); ``doc`` defaults to its docstring.
        """
        reactions = [Transition(EvCbSuccess[behavior, OrNavigation], following, SUCCESS),
                     Transition(EvCbFailure[behavior, OrNavigation], on_failure or following, ABORT)]
        configs = ((OrNavigation, behavior, args), (OrLED, led, ()))
        return self._declare(name, base, reactions, configs, doc if doc is not None else base.__doc__)

    def forward(self, name: str, length: float, *, led: type[ISmaccClientBehavior], following: str,
                doc: str) -> type[SmaccState]:
        """Drive ``length`` m straight ahead at the dance's forward speed."""
        return self.motion(name, CbNavigateForward, length, wp.FORWARD_SPEED, led=led, following=following,
                           doc=doc)

    def _declare(self, name: str, base: type[SmaccState], reactions: list[Transition],
                 configs: tuple[tuple[Any, type[ISmaccClientBehavior], tuple[Any, ...]], ...],
                 doc: str | None) -> type[SmaccState]:
        @classmethod  # type: ignore[misc]
        def static_configure(cls: type[SmaccState]) -> None:
            for orthogonal, behavior, args in configs:
                cls.configure_orthogonal(orthogonal, behavior, *args)

        namespace = {"superstate": self.superstate, "reactions": reactions,
                     "static_configure": static_configure, "__doc__": doc, "__module__": self.module,
                     "__qualname__": name}
        return type(name, (base,), namespace, parent=self.superstate)
