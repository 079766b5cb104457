"""``StState1`` (MsRun's first state): StState2 on its countdown, on any sensor message or on ``n``; Ss1
on ``p``; MsRecover on EvFail."""

from __future__ import annotations

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import ABORT, EvKeyPressN, EvKeyPressP, EvTimer, EvTopicMessage, Transition
from smacc_py.state_machines.sm_three_some.clients.cl_subscriber import ClSubscriber
from smacc_py.state_machines.sm_three_some.events import EvFail
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrSubscriber, OrTimer
from smacc_py.state_machines.sm_three_some.states.common import (
    LoggedState,
    configure_timeout_keys_and_sensor,
)
from smacc_py.state_machines.sm_three_some.tags import NEXT, PREVIOUS, TIMEOUT


class StState1(LoggedState, parent="MsRun"):
    """Wait for the countdown, a key or a sensor message."""

    reactions = [
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StState2", TIMEOUT),
        Transition(EvTopicMessage[ClSubscriber, OrSubscriber], "StState2", TIMEOUT),
        Transition(EvKeyPressP[CbDefaultKeyboardBehavior, OrKeyboard], "Ss1", PREVIOUS),
        Transition(EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard], "StState2", NEXT),
        Transition(EvFail, "MsRecover", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        configure_timeout_keys_and_sensor(cls)
