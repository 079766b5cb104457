"""Definition errors fail at class definition or at start, with a message naming the class at fault."""


from __future__ import annotations

import importlib
import pkgutil

import pytest

import smacc_py.state_machines
from smacc_py.core import (
    SUCCESS,
    EvCbSuccess,
    History,
    InvalidDefinitionError,
    Orthogonal,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccState,
    SmaccStateMachineBase,
    SrEventCountdown,
    Transition,
)


class EvGo(SmaccEvent):
    pass


class OrUsed(Orthogonal):
    pass


class OrForgotten(Orthogonal):
    pass


class CbMove(SmaccClientBehavior):
    def __init__(self, x: float, y: float) -> None:
        self.x, self.y = x, y


def test_invalid_target_object_raises_at_definition() -> None:
    with pytest.raises(InvalidDefinitionError, match=r"Transition\(EvGo, \.\.\.\) target must be a state"):
        Transition(EvGo, 42)  # type: ignore[arg-type]
    with pytest.raises(InvalidDefinitionError, match=r"StBadList\.reactions\[0\] is not a Transition"):
        class StBadList(SmaccState):
            reactions = [EvGo]
    with pytest.raises(InvalidDefinitionError, match="tag must be a TransitionTag"):
        Transition(EvGo, "StX", "SUCCESS")  # type: ignore[arg-type]
    with pytest.raises(InvalidDefinitionError, match="event must be a SmaccEvent class"):
        Transition(int, "StX")  # type: ignore[arg-type]


def test_target_that_is_not_a_state_raises_naming_the_state() -> None:
    class SmNotState(SmaccStateMachineBase):
        initial_state = "StOrigin"

    class StOrigin(SmaccState, parent=SmNotState):
        reactions = [Transition(EvGo, OrUsed)]

    with pytest.raises(InvalidDefinitionError, match=r"StOrigin\.reactions\[0\].*OrUsed.*not a SmaccState"):
        SmNotState()


def test_unknown_target_name_raises_at_instantiation_naming_state_and_name() -> None:
    class SmTypo(SmaccStateMachineBase):
        initial_state = "StHere"

    class StHere(SmaccState, parent=SmTypo):
        reactions = [Transition(EvGo, "StThere", SUCCESS)]

    class StThere1(SmaccState, parent=SmTypo):
        pass

    with pytest.raises(InvalidDefinitionError, match=r"StHere\.reactions\[0\].*unknown state 'StThere' "
                                                     r"\(states of SmTypo: StHere, StThere1\)"):
        SmTypo()


def test_behavior_on_an_orthogonal_the_machine_does_not_create_raises_at_start() -> None:
    class SmMissingOr(SmaccStateMachineBase):
        initial_state = "StNeedsOr"

        def on_initialize(self) -> None:
            self.create_orthogonal(OrUsed)

    class StNeedsOr(SmaccState, parent=SmMissingOr):
        @classmethod
        def static_configure(cls) -> None:
            cls.configure_orthogonal(OrForgotten, CbMove, 1.0, 2.0)

    sm = SmMissingOr()
    with pytest.raises(InvalidDefinitionError, match="StNeedsOr configures CbMove on OrForgotten, but "
                                                     r"SmMissingOr.on_initialize does not create OrForgotten "
                                                     r"\(created: OrUsed\)"):
        sm.start()


def test_unreachable_state_raises_naming_it() -> None:
    class SmIsland(SmaccStateMachineBase):
        initial_state = "StMainland"

    class StMainland(SmaccState, parent=SmIsland):
        pass

    class StIsland(SmaccState, parent=SmIsland):
        reactions = [Transition(EvGo, StMainland)]

    with pytest.raises(InvalidDefinitionError, match=r"SmIsland: state\(s\) StIsland are "
                                                     "declared but unreachable"):
        SmIsland.validate()


def test_free_top_level_state_that_nothing_reaches_raises_at_start_naming_it() -> None:
    class StPatrol(SmaccState):
        pass

    class StDock(SmaccState):
        reactions = [Transition(EvGo, StPatrol)]

    class StForgotten(SmaccState):  # leads into the machine, but no transition leads here
        reactions = [Transition(EvGo, StDock)]

    class SmFree(SmaccStateMachineBase):
        initial_state = StDock

    with pytest.raises(InvalidDefinitionError, match=r"SmFree: state\(s\) StForgotten are declared but "
                                                     "unreachable from the initial state StDock"):
        SmFree()


def test_free_states_reached_and_free_templates_pass() -> None:
    class _StTimed(SmaccState):  # a base other states subclass is a template, not a state
        pass

    class StEnd(_StTimed):
        pass

    class StStart(_StTimed):
        reactions = [Transition(EvGo, StEnd)]

    class SmFreeOk(SmaccStateMachineBase):
        initial_state = StStart

    sm = SmFreeOk()
    sm.start()
    sm.post_event(EvGo)
    sm.process_events()
    assert sm.current_state_names() == ["StEnd"]


def test_unreachable_inner_state_of_a_free_superstate_raises_naming_it() -> None:
    class SsFree(SmaccState):
        pass

    class StiFirst(SmaccState, parent=SsFree):
        pass

    class StiLost(SmaccState, parent=SsFree):
        pass

    SsFree.inner_initial_state = StiFirst

    class SmSuper(SmaccStateMachineBase):
        initial_state = SsFree

    with pytest.raises(InvalidDefinitionError, match=r"SmSuper: state\(s\) StiLost are declared but "
                                                     "unreachable"):
        SmSuper()


def _shipped_machines() -> list[str]:
    return sorted(m.name for m in pkgutil.iter_modules(smacc_py.state_machines.__path__) if m.ispkg)


@pytest.mark.parametrize("name", _shipped_machines())
def test_every_shipped_state_machine_passes_the_definition_checks(name: str) -> None:
    machine = importlib.import_module(f"smacc_py.state_machines.{name}").STATE_MACHINE
    model = machine.validate()
    assert model.initial is not None


def test_bad_static_configuration_raises_at_class_definition() -> None:
    with pytest.raises(InvalidDefinitionError, match=r"StBadArgs: bad arguments for CbMove\(.*"
                                                     "missing a required argument: 'y'"):
        class StBadArgs(SmaccState):
            @classmethod
            def static_configure(cls) -> None:
                cls.configure_orthogonal(OrUsed, CbMove, 1.0)
    with pytest.raises(InvalidDefinitionError, match=r"StBadOr\.configure_orthogonal: .*CbMove"
                                                     " is not an Orthogonal"):
        class StBadOr(SmaccState):
            @classmethod
            def static_configure(cls) -> None:
                cls.configure_orthogonal(CbMove, CbMove)  # type: ignore[arg-type]
    with pytest.raises(InvalidDefinitionError, match="StNoInputs: reactor SrEventCountdown "
                                                     "needs at least one"):
        class StNoInputs(SmaccState):
            @classmethod
            def static_configure(cls) -> None:
                cls.static_create_state_reactor(SrEventCountdown, EvGo, [], 2)
    with pytest.raises(InvalidDefinitionError, match="may only be called from static_configure"):
        class StLate(SmaccState):
            pass

        StLate.configure_orthogonal(OrUsed, CbMove, 1.0, 2.0)


def test_hierarchy_errors_name_the_superstate() -> None:
    class SmTree(SmaccStateMachineBase):
        initial_state = "SsNoInitial"

    class SsNoInitial(SmaccState, parent=SmTree):
        pass

    class StiChild(SmaccState, parent=SsNoInitial):
        pass

    with pytest.raises(InvalidDefinitionError, match=r"SsNoInitial has inner states \(StiChild\) "
                                                     "but declares no inner_initial_state"):
        SmTree()

    class SmHist(SmaccStateMachineBase):
        initial_state = "StFlat"

    class StFlat(SmaccState, parent=SmHist):
        reactions = [Transition(EvCbSuccess, History("StFlat"))]

    with pytest.raises(InvalidDefinitionError, match=r"History\(\) needs a superstate, StFlat "
                                                     "has no inner states"):
        SmHist()
    with pytest.raises(InvalidDefinitionError, match="StWrongParent: parent must be a SmaccState"):
        class StWrongParent(SmaccState, parent=OrUsed):
            pass
    with pytest.raises(InvalidDefinitionError, match=r"SmBadInitial\.initial_state must be a SmaccState"):
        class SmBadInitial(SmaccStateMachineBase):
            initial_state = OrUsed  # type: ignore[assignment]
