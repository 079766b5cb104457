"""A machine split across modules needs no import tricks: ``parent="Name"`` is resolved when the machine
is compiled, so mode states, superstates and inner states may be defined in any order and in modules that
never import the machine; a name that resolves to nothing fails naming the state and the machine."""

from __future__ import annotations

import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

from smacc_py.core import (
    SUCCESS,
    History,
    InvalidDefinitionError,
    SmaccEvent,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.ros.loader import load_state_machine
from smacc_py.testing import MachineHarness


class EvNext(SmaccEvent):
    """Next inner state."""


class EvFault(SmaccEvent):
    """Run mode → recovery mode."""


class EvRecovered(SmaccEvent):
    """Recovery mode → back where the run mode was (deep history)."""


class RESUME(SUCCESS):
    """Tag of the history transition."""


def test_mode_states_and_inner_states_defined_before_their_parents_run_with_history() -> None:
    class StiRecovering(SmaccState, parent="MsRecoveryMode"):  # before its superstate, which is below
        reactions = (Transition(EvRecovered, History("MsRunMode"), RESUME),)

    class StiWorking(SmaccState, parent="MsRunMode"):
        reactions = (Transition(EvNext, "StiResting"),)

    class StiResting(SmaccState, parent="MsRunMode"):
        pass

    class MsRunMode(SmaccState, parent="SmAnyOrder"):  # before the machine
        inner_initial_state = "StiWorking"
        reactions = (Transition(EvFault, "MsRecoveryMode"),)

    class MsRecoveryMode(SmaccState, parent="SmAnyOrder"):
        inner_initial_state = "StiRecovering"

    class SmAnyOrder(SmaccStateMachineBase):
        initial_state = "MsRunMode"

    model = SmAnyOrder.validate()
    assert model.states[StiResting].parent is MsRunMode and model.states[MsRunMode].level == 0
    with MachineHarness(SmAnyOrder) as harness:
        sm = harness.sm
        assert sm.current_state_names() == ["MsRunMode", "StiWorking"]
        for event, expected in ((EvNext, ["MsRunMode", "StiResting"]),
                                (EvFault, ["MsRecoveryMode", "StiRecovering"]),
                                (EvRecovered, ["MsRunMode", "StiResting"])):  # deep history
            sm.post_event(event())
            sm.process_events()
            assert sm.current_state_names() == expected
        assert harness.transitions()[-1] == ("StiRecovering", "MsRunMode", "RESUME")


SPLIT_FILES = {
    "__init__.py": "from .sm_split import SmSplitFiles\n\nSTATE_MACHINE = SmSplitFiles\n",
    # inner states first, in a module that imports neither the mode state nor the machine
    "inner.py": textwrap.dedent('''
        from smacc_py.core import SmaccState, Transition

        from .events import EvNext


        class StiA(SmaccState, parent="MsRun"):
            reactions = (Transition(EvNext, "StiB"),)


        class StiB(SmaccState, parent="MsRun"):
            pass
    '''),
    "events.py": "from smacc_py.core import SmaccEvent\n\n\nclass EvNext(SmaccEvent):\n    pass\n",
    "modes.py": textwrap.dedent('''
        from smacc_py.core import SmaccState


        class MsRun(SmaccState, parent="SmSplitFiles"):
            inner_initial_state = "StiA"
    '''),
    "sm_split.py": textwrap.dedent('''
        from smacc_py.core import SmaccStateMachineBase

        from . import inner, modes  # noqa: F401  (registers the states)


        class SmSplitFiles(SmaccStateMachineBase):
            initial_state = "MsRun"
    '''),
}


@pytest.fixture
def split_package(tmp_path: Path) -> Iterator[Path]:
    package = tmp_path / "sm_split_files"
    package.mkdir()
    for name, text in SPLIT_FILES.items():
        (package / name).write_text(text)
    path, modules = list(sys.path), set(sys.modules)
    yield package
    sys.path[:] = path
    for name in set(sys.modules) - modules:
        del sys.modules[name]


def test_a_machine_split_across_modules_needs_no_import_trick(split_package: Path) -> None:
    sm_type = load_state_machine(str(split_package))
    with MachineHarness(sm_type) as harness:
        assert harness.sm.current_state_names() == ["MsRun", "StiA"]
        harness.sm.post_event(sys.modules["sm_split_files.events"].EvNext())
        harness.sm.process_events()
        assert harness.sm.current_state_names() == ["MsRun", "StiB"]


def test_a_parent_name_that_names_no_state_fails_naming_the_state_and_the_machine() -> None:
    class StiLost(SmaccState, parent="MsRunModee"):  # a typo: MsRunMode
        pass

    class MsRunMode(SmaccState, parent="SmTypo"):
        inner_initial_state = "StiInside"

    class StiInside(SmaccState, parent="MsRunMode"):
        pass

    class SmTypo(SmaccStateMachineBase):
        initial_state = "MsRunMode"

    with pytest.raises(InvalidDefinitionError) as caught:
        SmTypo.validate()
    assert "StiLost" in str(caught.value) and "parent='MsRunModee'" in str(caught.value)
    assert "names no state of SmTypo" in str(caught.value)
    assert "MsRunMode, StiInside" in str(caught.value)  # the states it could have meant


def test_a_transition_to_an_unknown_name_fails_naming_the_state_and_the_machine() -> None:
    class StStart(SmaccState, parent="SmUnknownTarget"):
        reactions = (Transition(EvNext, "StNowhere"),)

    class SmUnknownTarget(SmaccStateMachineBase):
        initial_state = StStart

    with pytest.raises(InvalidDefinitionError, match=r"StStart\.reactions\[0\].*unknown state 'StNowhere' "
                                                     r"\(states of SmUnknownTarget: StStart\)"):
        SmUnknownTarget.validate()


def test_a_parent_name_reached_from_another_machine_names_that_machine() -> None:
    class StMine(SmaccState, parent="SmOwner"):
        pass

    class SmOwner(SmaccStateMachineBase):
        initial_state = StMine

    class SmThief(SmaccStateMachineBase):
        initial_state = StMine

    assert SmOwner.validate().initial is StMine
    with pytest.raises(InvalidDefinitionError, match=r"StMine: parent='SmOwner' names no state of SmThief"):
        SmThief.validate()


def test_two_machines_next_to_each_other_keep_their_named_states_apart() -> None:
    class StLeft(SmaccState, parent="SmLeft"):
        pass

    class StRight(SmaccState, parent="SmRight"):
        pass

    class SmLeft(SmaccStateMachineBase):
        initial_state = "StLeft"

    class SmRight(SmaccStateMachineBase):
        initial_state = "StRight"

    assert list(SmLeft.validate().states) == [StLeft]
    assert list(SmRight.validate().states) == [StRight]


def test_a_parent_that_is_not_a_class_name_fails_at_class_creation() -> None:
    with pytest.raises(InvalidDefinitionError, match=r"StOdd: parent='Ms Run' is not a class name"):
        class StOdd(SmaccState, parent="Ms Run"):
            pass


def _factory(tag: str) -> type[SmaccStateMachineBase]:
    """The same class names on every call, as a test helper that builds one machine per call would."""

    class StFirst(SmaccState, parent="SmFactory"):
        reactions = (Transition(EvNext, "StSecond"),)
        label = tag

    class StSecond(SmaccState, parent="SmFactory"):
        pass

    class SmFactory(SmaccStateMachineBase):
        initial_state = "StFirst"

    return SmFactory


def test_a_factory_run_twice_binds_each_machine_to_its_own_states() -> None:
    first = _factory("one")
    assert first.validate().initial.label == "one"  # type: ignore[attr-defined]
    second = _factory("two")
    assert second.validate().initial.label == "two"  # type: ignore[attr-defined]
    assert set(first.validate().states).isdisjoint(second.validate().states)


def test_a_state_defined_again_before_its_machine_is_built_replaces_the_first() -> None:
    """As a notebook cell run twice: the newer definition is the one the machine gets."""
    first = _factory("old")
    second = _factory("new")  # the same states again, before any machine was built
    assert first.validate().initial.label == "new"  # type: ignore[attr-defined]
    assert second is not first
