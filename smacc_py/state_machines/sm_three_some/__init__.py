"""sm_three_some: SMACC2's reference machine with mode states, superstates, loops, a keyboard, a
countdown timer, a subscriber and a state reactor (smacc2_sm_reference_library/sm_three_some).

MsRun holds StState1 → StState2 → StState3 → Ss1 → Ss2 → StState4. Each simple state leaves on the
EvTimer of a CbTimerCountdownOnce(10) on a ClRosTimer ticking every 0.5 s (5 s), and on the keys
``n`` (next) and ``p`` (previous); StState1 also leaves on any message of its subscriber (which listens
to /keyboard_unicode, so any key), StState2 also when ``a``, ``b`` and ``c`` were all pressed
(SrAllEventsGo). Ss1 and Ss2 loop five times through three inner states. StState4 is final: upstream
names its transition table ``transitions``, which SMACC2 does not read, so it has no reactions.
EvFail (nobody posts it) would go to MsRecover, whose EvToDeep returns by deep history.

Differences from C++, none visible on the graph: the inner states of Ss1 and Ss2 are distinct classes
here (``Ss1StiState1`` ..; C++ tells its two ``StiState1`` apart by namespace), and the
``configure_orthogonal<OrUpdatablePublisher, ...>`` lines are left out, as upstream never creates that
orthogonal (SMACC2 skips them with a log line; smacc_py refuses them). Run it with
``smacc-run sm_three_some`` and ``smacc-key n``.
"""

from smacc_py.state_machines.sm_three_some.sm_three_some import (
    NOMINAL_TRANSITIONS,
    TICK_S,
    EvFail,
    EvToDeep,
    SmThreeSome,
)

STATE_MACHINE = SmThreeSome

__all__ = ["NOMINAL_TRANSITIONS", "STATE_MACHINE", "TICK_S", "EvFail", "EvToDeep", "SmThreeSome"]
