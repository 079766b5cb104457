"""``StState2``: StState3 on its countdown, on ``n`` or once ``a``, ``b`` and ``c`` were pressed
(SrAllEventsGo); StState1 on ``p``."""

from __future__ import annotations

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import (
    EvAllGo,
    EvKeyPressA,
    EvKeyPressB,
    EvKeyPressC,
    EvKeyPressN,
    EvKeyPressP,
    EvTimer,
    SrAllEventsGo,
    Transition,
)
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrTimer
from smacc_py.state_machines.sm_three_some.states.common import (
    LoggedState,
    configure_timeout_keys_and_sensor,
)
from smacc_py.state_machines.sm_three_some.tags import NEXT, PREVIOUS, TIMEOUT

#: SrAllEventsGo's output (``EvAllGo<SrAllEventsGo>``).
EV_ALL_GO = EvAllGo[SrAllEventsGo, "StState2"]  # type: ignore[type-arg]


class StState2(LoggedState, parent="MsRun"):
    """Wait for the countdown, ``n``, ``p``, or all of ``a``, ``b`` and ``c``."""

    reactions = [
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StState3", TIMEOUT),
        Transition(EV_ALL_GO, "StState3"),
        Transition(EvKeyPressP[CbDefaultKeyboardBehavior, OrKeyboard], "StState1", PREVIOUS),
        Transition(EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard], "StState3", NEXT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        configure_timeout_keys_and_sensor(cls)
        cls.static_create_state_reactor(
            SrAllEventsGo, EV_ALL_GO,
            [key[CbDefaultKeyboardBehavior, OrKeyboard] for key in (EvKeyPressA, EvKeyPressB, EvKeyPressC)])
