"""Dispatch and lifecycle semantics of the core engine (synchronous mode, no threads)."""


from __future__ import annotations

import logging

import pytest

from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvCbSuccess,
    EvLoopContinue,
    EvLoopEnd,
    History,
    Orthogonal,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccEventGenerator,
    SmaccLookupError,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    StateReactor,
    Transition,
)


class EvGo(SmaccEvent):
    pass


class EvNext(SmaccEvent):
    pass


class EvValue(SmaccEvent):
    pass


def keys(sm: SmaccStateMachineBase) -> list[tuple[str, str, str]]:
    return [r.key() for r in sm.transition_log]


class Traced(SmaccState):
    """Appends every hook call to ``sm.trace``."""

    def runtime_configure(self) -> None:
        self.sm.trace.append(f"{type(self).__name__}.runtime_configure")

    def on_entry(self) -> None:
        self.sm.trace.append(f"{type(self).__name__}.on_entry")

    def on_exit(self) -> None:
        self.sm.trace.append(f"{type(self).__name__}.on_exit")


class TracingMachine(SmaccStateMachineBase):
    def __init__(self) -> None:
        super().__init__()
        self.trace: list[str] = []


# ----------------------------------------------------------------------------- lifecycle order
class OrA(Orthogonal):
    pass


class CbTrace(SmaccClientBehavior):
    def __init__(self, label: str) -> None:
        self.label = label

    def runtime_configure(self) -> None:
        self.sm.trace.append(f"Cb({self.label}).runtime_configure")

    def on_entry(self) -> None:
        self.sm.trace.append(f"Cb({self.label}).on_entry")

    def on_exit(self) -> None:
        self.sm.trace.append(f"Cb({self.label}).on_exit")


class SrTrace(StateReactor):
    def on_entry(self) -> None:
        self.sm.trace.append("Sr.on_entry")

    def on_exit(self) -> None:
        self.sm.trace.append("Sr.on_exit")


class EgTrace(SmaccEventGenerator):
    def on_entry(self) -> None:
        self.sm.trace.append("Eg.on_entry")

    def on_exit(self) -> None:
        self.sm.trace.append("Eg.on_exit")


class SmOrder(TracingMachine):
    initial_state = "SsOuter"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrA)


class SsOuter(Traced, parent=SmOrder):
    inner_initial_state = "StiA"

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrA, CbTrace, "outer")


class StiA(Traced, parent=SsOuter):
    reactions = [Transition(EvGo, "StB", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrA, CbTrace, "a")
        cls.static_create_state_reactor(SrTrace, EvNext, [EvValue])
        cls.static_create_event_generator(EgTrace)

    def on_exit_SUCCESS(self) -> None:
        self.sm.trace.append("StiA.on_exit_SUCCESS")


class StB(Traced, parent=SmOrder):
    pass


class TransitionTracer(SmaccObserver):
    def on_transition(self, sm: SmaccStateMachineBase, record: object) -> None:
        sm.trace.append("transition")


def test_entry_and_exit_order_across_superstates_matches_smacc2() -> None:
    sm = SmOrder()
    sm.add_observer(TransitionTracer())
    sm.start()
    assert sm.trace == [
        "SsOuter.runtime_configure", "Cb(outer).runtime_configure", "SsOuter.on_entry", "Cb(outer).on_entry",
        "StiA.runtime_configure", "Cb(a).runtime_configure", "StiA.on_entry", "Cb(a).on_entry",
        "Sr.on_entry", "Eg.on_entry",
    ]
    assert [len(level) for level in sm.get_orthogonal(OrA).behavior_stack] == [1, 1]
    sm.trace.clear()
    sm.post_event(EvGo)
    sm.process_events()
    assert sm.trace == [
        "StiA.on_exit_SUCCESS", "transition",
        "Cb(a).on_exit", "Sr.on_exit", "Eg.on_exit", "StiA.on_exit",
        "Cb(outer).on_exit", "SsOuter.on_exit",
        "StB.runtime_configure", "StB.on_entry",
    ]
    assert sm.get_orthogonal(OrA).behavior_stack == [[]]
    assert sm.current_state_names() == ["StB"]


# ----------------------------------------------------------------------------- self transitions
class SmSelf(TracingMachine):
    initial_state = "SsHost"


class SsHost(Traced, parent=SmSelf):
    inner_initial_state = "StiLoop"
    reactions = [Transition(EvNext, "SsHost")]


class StiLoop(Traced, parent=SsHost):
    reactions = [Transition(EvGo, "StiLoop", ABORT)]


def test_self_transition_reruns_exit_and_entry_without_leaving_the_parent() -> None:
    sm = SmSelf()
    sm.start()
    first = sm.current_state
    sm.trace.clear()
    sm.post_event(EvGo)
    sm.process_events()
    assert sm.trace == ["StiLoop.on_exit", "StiLoop.runtime_configure", "StiLoop.on_entry"]
    assert sm.current_state is not first and type(sm.current_state) is StiLoop
    assert keys(sm) == [("StiLoop", "StiLoop", "ABORT")]


def test_superstate_self_transition_exits_and_reenters_its_inner_states() -> None:
    sm = SmSelf()
    sm.start()
    sm.trace.clear()
    sm.post_event(EvNext)
    sm.process_events()
    assert sm.trace == [
        "StiLoop.on_exit", "SsHost.on_exit",
        "SsHost.runtime_configure", "SsHost.on_entry", "StiLoop.runtime_configure", "StiLoop.on_entry",
    ]


# ----------------------------------------------------------------------------- first match, innermost first
class SmMatch(SmaccStateMachineBase):
    initial_state = "SsParent"


class SsParent(SmaccState, parent=SmMatch):
    inner_initial_state = "StiFirst"
    reactions = [Transition(EvGo, "StOuterTarget"), Transition(EvValue, "StOuterTarget")]


class StiFirst(SmaccState, parent=SsParent):
    reactions = [
        Transition(EvGo, "StiSecond", SUCCESS),
        Transition(EvGo, "StOuterTarget", ABORT),
        Transition(EvCbSuccess, "StiThird"),
    ]


class StiSecond(SmaccState, parent=SsParent):
    pass


class StiThird(SmaccState, parent=SsParent):
    pass


class StOuterTarget(SmaccState, parent=SmMatch):
    pass


def test_first_matching_transition_in_declaration_order_wins() -> None:
    sm = SmMatch()
    sm.start()
    sm.post_event(EvGo)
    sm.process_events()
    assert keys(sm) == [("StiFirst", "StiSecond", "SUCCESS")]


def test_innermost_state_reacts_first_then_ancestors() -> None:
    sm = SmMatch()
    sm.start()
    sm.post_event(EvGo)  # StiFirst handles it
    sm.post_event(EvGo)  # StiSecond has no reaction: SsParent handles it
    sm.process_events()
    assert keys(sm) == [("StiFirst", "StiSecond", "SUCCESS"), ("SsParent", "StOuterTarget", "DEFAULT")]
    assert sm.current_state_names() == ["StOuterTarget"]


def test_template_transition_matches_every_parameterisation_with_default_tag() -> None:
    class CbX(SmaccClientBehavior):
        pass

    sm = SmMatch()
    sm.start()
    sm.post_event(EvCbSuccess[CbX, OrA])
    sm.process_events()
    assert keys(sm) == [("StiFirst", "StiThird", "SUCCESS")]  # EvCbSuccess's default tag


# ----------------------------------------------------------------------------- guards
class SmGuard(SmaccStateMachineBase):
    initial_state = "StMeasure"


class StMeasure(SmaccState, parent=SmGuard):
    reactions = [
        Transition(EvValue, "StHigh", SUCCESS, guard=lambda ev: ev.value > 3),
        Transition(EvValue, "StLow", ABORT, guard=lambda ev: ev.value >= 0),
    ]


class StHigh(SmaccState, parent=SmGuard):
    reactions = [Transition(EvValue, "StMeasure", guard=lambda ev: ev.missing_field)]


class StLow(SmaccState, parent=SmGuard):
    pass


@pytest.mark.parametrize(("value", "target"), [(5, "StHigh"), (1, "StLow")])
def test_guards_see_the_event_payload(value: int, target: str) -> None:
    sm = SmGuard()
    sm.start()
    sm.post_event(EvValue(value=value))
    sm.process_events()
    assert sm.current_state_names() == [target]
    assert sm.transition_log[-1].event.value == value


def test_event_rejected_by_every_guard_is_unhandled() -> None:
    sm = SmGuard()
    sm.start()
    sm.post_event(EvValue(value=-1))
    sm.process_events()
    assert keys(sm) == [] and sm.current_state_names() == ["StMeasure"]


def test_raising_guard_counts_as_false_and_is_logged(caplog: pytest.LogCaptureFixture) -> None:
    sm = SmGuard()
    sm.start()
    sm.post_event(EvValue(value=9))
    with caplog.at_level(logging.ERROR, logger="smacc_py"):
        sm.post_event(EvValue(value=9))
        sm.process_events()
    assert sm.current_state_names() == ["StHigh"]
    assert "guard of" in caplog.text and "AttributeError" in caplog.text


# ----------------------------------------------------------------------------- unhandled events
def test_unhandled_event_is_logged_and_reported(caplog: pytest.LogCaptureFixture) -> None:
    seen: list[SmaccEvent] = []

    class Watch(SmaccObserver):
        def on_event_unhandled(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
            seen.append(event)

    sm = SmGuard()
    sm.add_observer(Watch())
    sm.start()
    with caplog.at_level(logging.DEBUG, logger="smacc_py"):
        sm.post_event(EvNext)
        sm.process_events()
    assert "unhandled event EvNext()" in caplog.text and "StMeasure" in caplog.text
    assert [type(e) for e in seen] == [EvNext]


# ----------------------------------------------------------------------------- deep history
class EvError(SmaccEvent):
    pass


class EvResume(SmaccEvent):
    pass


class SmHistory(TracingMachine):
    initial_state = "StBoot"


class StBoot(Traced, parent=SmHistory):
    reactions = [Transition(EvGo, History("MsRun"))]


class MsRun(Traced, parent=SmHistory):
    inner_initial_state = "StiStep1"
    reactions = [Transition(EvError, "MsRecovery", ABORT)]


class StiStep1(Traced, parent=MsRun):
    reactions = [Transition(EvNext, "SsStep2")]


class SsStep2(Traced, parent=MsRun):
    inner_initial_state = "StiDeepA"


class StiDeepA(Traced, parent=SsStep2):
    reactions = [Transition(EvNext, "StiDeepB")]


class StiDeepB(Traced, parent=SsStep2):
    pass


class MsRecovery(Traced, parent=SmHistory):
    reactions = [Transition(EvResume, History(MsRun), SUCCESS)]


def test_history_without_a_previous_visit_enters_the_inner_initial_state() -> None:
    sm = SmHistory()
    sm.start()
    sm.post_event(EvGo)
    sm.process_events()
    assert sm.current_state_names() == ["MsRun", "StiStep1"]
    assert sm.transition_log[-1].history is True


def test_history_resumes_the_last_active_leaf() -> None:
    sm = SmHistory()
    sm.start()
    for event in (EvGo, EvNext, EvNext, EvError):
        sm.post_event(event)
    sm.process_events()
    assert sm.current_state_names() == ["MsRecovery"]
    sm.trace.clear()
    sm.post_event(EvResume)
    sm.process_events()
    assert sm.current_state_names() == ["MsRun", "SsStep2", "StiDeepB"]
    assert sm.trace == [
        "MsRecovery.on_exit",
        "MsRun.runtime_configure", "MsRun.on_entry",
        "SsStep2.runtime_configure", "SsStep2.on_entry",
        "StiDeepB.runtime_configure", "StiDeepB.on_entry",
    ]
    last = sm.transition_log[-1]
    assert (last.key(), last.leaf, last.history) == (("MsRecovery", "MsRun", "SUCCESS"), StiDeepB, True)


# ----------------------------------------------------------------------------- loops and global data
class SmLoop(SmaccStateMachineBase):
    initial_state = "StLoop"


class StLoop(SmaccState, parent=SmLoop):
    reactions = [
        Transition(EvLoopContinue["StLoop"], "StLoop"),
        Transition(EvLoopEnd["StLoop"], "StDone"),
    ]

    def on_entry(self) -> None:
        count = self.get_global_sm_data("iterations", 0)
        self.set_global_sm_data("iterations", count + 1)
        self.check_while_loop_condition_and_throw_event(lambda: count < 3)


class StDone(SmaccState, parent=SmLoop):
    pass


def test_loop_helper_posts_continue_then_end_with_derived_tags() -> None:
    sm = SmLoop()
    sm.start()
    sm.process_events()
    assert keys(sm) == [("StLoop", "StLoop", "CONTINUELOOP")] * 3 + [("StLoop", "StDone", "ENDLOOP")]
    assert sm.get_global_sm_data("iterations") == 4
    assert sm.model.plans[StLoop][0].event is EvLoopContinue[StLoop]  # forward reference resolved


def test_global_data_defaults_and_missing_names() -> None:
    sm = SmGuard()
    sm.set_global_sm_data("count", 2)
    assert sm.get_global_sm_data("count") == 2
    assert sm.get_global_sm_data("absent", None) is None
    with pytest.raises(SmaccLookupError, match=r"'absent'.*known: count"):
        sm.get_global_sm_data("absent")
    assert sm.global_data.as_status() == (["count"], ["2"])
    with pytest.raises(ValueError, match="non-empty string"):
        sm.set_global_sm_data("", 1)
