"""``MsRecover``: the recovery mode; EvToDeep returns to MsRun's last inner state (deep history)."""

from __future__ import annotations

from smacc_py.core import SUCCESS, History, SmaccState, Transition
from smacc_py.state_machines.sm_three_some.events import EvToDeep


class MsRecover(SmaccState, parent="SmThreeSome"):
    """Waits for EvToDeep (``deep_history<MsRun::LastDeepState>``)."""

    reactions = [Transition(EvToDeep, History("MsRun"), SUCCESS)]
