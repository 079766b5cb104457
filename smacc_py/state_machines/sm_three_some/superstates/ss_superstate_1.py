"""``Ss1``: ``SmaccState<Ss1, MsRun, StiState1>``; five iterations, then Ss2 (EvLoopEnd<StiState1>)."""

from __future__ import annotations

from smacc_py.core import EvLoopEnd, Transition
from smacc_py.state_machines.sm_three_some.superstates.looping import LoopingSuperstate, declare_inner_states


class Ss1(LoopingSuperstate, parent="MsRun"):
    """Loops Ss1StiState1 → Ss1StiState2 → Ss1StiState3 five times."""

    inner_initial_state = "Ss1StiState1"
    reactions = [Transition(EvLoopEnd["Ss1StiState1"], "Ss2")]


Ss1StiState1, Ss1StiState2, Ss1StiState3 = declare_inner_states("Ss1", __name__)
