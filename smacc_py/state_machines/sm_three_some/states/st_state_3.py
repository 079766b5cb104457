"""``StState3``: Ss1 on its countdown or ``n``; StState2 on ``p``."""

from __future__ import annotations

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import EvKeyPressN, EvKeyPressP, EvTimer, Transition
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrTimer
from smacc_py.state_machines.sm_three_some.states.common import (
    LoggedState,
    configure_timeout_keys_and_sensor,
)
from smacc_py.state_machines.sm_three_some.tags import NEXT, PREVIOUS, TIMEOUT


class StState3(LoggedState, parent="MsRun"):
    """Wait for the countdown, ``n`` or ``p``."""

    reactions = [
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "Ss1", TIMEOUT),
        Transition(EvKeyPressP[CbDefaultKeyboardBehavior, OrKeyboard], "StState2", PREVIOUS),
        Transition(EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard], "Ss1", NEXT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        configure_timeout_keys_and_sensor(cls)
