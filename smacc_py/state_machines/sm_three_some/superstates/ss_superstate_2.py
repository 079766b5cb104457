"""``Ss2``: ``SmaccState<Ss2, MsRun, StiState1>``; five iterations, then StState4 (EvLoopEnd<StiState1>)."""

from __future__ import annotations

from smacc_py.core import EvLoopEnd, Transition
from smacc_py.state_machines.sm_three_some.superstates.looping import LoopingSuperstate, declare_inner_states


class Ss2(LoopingSuperstate, parent="MsRun"):
    """Loops Ss2StiState1 → Ss2StiState2 → Ss2StiState3 five times."""

    inner_initial_state = "Ss2StiState1"
    reactions = [Transition(EvLoopEnd["Ss2StiState1"], "StState4")]


Ss2StiState1, Ss2StiState2, Ss2StiState3 = declare_inner_states("Ss2", __name__)
