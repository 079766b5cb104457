"""``MsRun``: ``SmaccState<MsRun, SmThreeSome, StState1>``, the mode the machine works in."""

from __future__ import annotations

from smacc_py.core import SmaccState


class MsRun(SmaccState, parent="SmThreeSome"):
    """StState1 .. StState4 and the two looping superstates."""

    inner_initial_state = "StState1"
