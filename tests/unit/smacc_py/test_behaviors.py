"""Behaviors, reactors, generators, CURRENT_STATE lifetime, polling and the threaded mode."""


from __future__ import annotations

import logging
import threading

import pytest

from smacc_py.core import (
    ConditionalGeneratorMode,
    EgConditionalGenerator,
    EvAllGo,
    EvCbFailure,
    EvCbFinished,
    EvCbSuccess,
    EvConditionalTrue,
    EvCountdownEnd,
    EvFalse,
    EvTrue,
    ISmaccClient,
    ISmaccComponent,
    ISmaccUpdatable,
    Orthogonal,
    SmaccAsyncClientBehavior,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccLookupError,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    SrAllEventsGo,
    SrConditional,
    SrEventCountdown,
    Transition,
)

TIMEOUT_S = 5.0


class EvGo(SmaccEvent):
    pass


class EvA(SmaccEvent):
    pass


class EvB(SmaccEvent):
    pass


class EvValue(SmaccEvent):
    pass


class Recorder(SmaccObserver):
    def __init__(self) -> None:
        self.posted: list[type] = []
        self.dropped: list[type] = []

    def on_event_posted(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        self.posted.append(type(event))

    def on_event_dropped(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        self.dropped.append(type(event))


# ----------------------------------------------------------------------------- clients and lookups
class CpStore(ISmaccComponent):
    def on_initialize(self) -> None:
        self.initialized = True


class CpOther(ISmaccComponent):
    pass


class ClWork(ISmaccClient, ISmaccUpdatable):
    def __init__(self) -> None:
        self.updates: list[float] = []

    def update(self) -> None:
        self.updates.append(self.sm.now())


class OrWork(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClWork).create_component(CpStore)


class CbSync(SmaccClientBehavior):
    instances: list[CbSync] = []

    def on_entry(self) -> None:
        CbSync.instances.append(self)
        self.store = self.requires_component(CpStore)
        self.client = self.requires_client(ClWork)


class CbQuick(SmaccAsyncClientBehavior):
    def on_entry(self) -> None:
        pass


class CbReportsSuccess(SmaccAsyncClientBehavior):
    def on_entry(self) -> None:
        self.post_success_event(distance=3.5)


class CbRaises(SmaccAsyncClientBehavior):
    def on_entry(self) -> None:
        raise RuntimeError("boom")


class CbCooperative(SmaccAsyncClientBehavior):
    def on_entry(self) -> None:
        self.started = threading.Event()
        self.saw_shutdown = False
        self.started.set()
        while not self.wait_for_shutdown(0.01):
            pass
        self.saw_shutdown = True

    def on_exit(self) -> None:
        self.finished_before_exit = self.is_finished() or not self._thread.is_alive()


RELEASE_STUCK = threading.Event()


class CbStuck(SmaccAsyncClientBehavior):
    join_timeout_s = 0.05

    def on_entry(self) -> None:
        self.started = threading.Event()
        self.started.set()
        RELEASE_STUCK.wait(TIMEOUT_S)  # ignores the shutdown flag on purpose


class SmWork(SmaccStateMachineBase):
    initial_state = "StSync"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrWork)


class StSync(SmaccState, parent=SmWork):
    reactions = [Transition(EvGo, "StQuick"), Transition(EvA, "StStuck"), Transition(EvB, "StCoop")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbSync)


class StQuick(SmaccState, parent=SmWork):
    reactions = [Transition(EvCbFinished[CbQuick, OrWork], "StReport")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbQuick)


class StReport(SmaccState, parent=SmWork):
    reactions = [Transition(EvCbSuccess[CbReportsSuccess, OrWork], "StRaise",
                            guard=lambda ev: ev.distance == 3.5)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbReportsSuccess)


class StRaise(SmaccState, parent=SmWork):
    reactions = [Transition(EvCbFailure[CbRaises, OrWork], "StSync")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbRaises)


class StStuck(SmaccState, parent=SmWork):
    reactions = [Transition(EvGo, "StSync")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbStuck)


class StCoop(SmaccState, parent=SmWork):
    reactions = [Transition(EvGo, "StSync"), Transition(EvCbFinished[CbCooperative, OrWork], "StQuick")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWork, CbCooperative)


def _in(sm: SmaccStateMachineBase, name: str) -> bool:
    return sm.current_state_names() == [name]


def test_requires_client_and_component_find_sm_lifetime_objects() -> None:
    sm = SmWork()
    sm.start()
    behavior = CbSync.instances[-1]
    assert behavior.store.initialized and isinstance(behavior.client, ClWork)
    assert sm.current_state.get_client_behavior(OrWork, CbSync) is behavior
    with pytest.raises(SmaccLookupError, match="CbSync: no component of type CpOther"):
        behavior.requires_component(CpOther)
    with pytest.raises(SmaccLookupError, match="StSync: no client of type CbSync"):
        sm.current_state.requires_client(CbSync)


def test_async_chain_finished_success_with_payload_and_failure_on_exception(
        caplog: pytest.LogCaptureFixture) -> None:
    sm = SmWork()
    sm.start()
    sm.post_event(EvGo)
    with caplog.at_level(logging.ERROR, logger="smacc_py"):
        # StQuick → (EvCbFinished) StReport → (EvCbSuccess, distance=3.5) StRaise → (EvCbFailure) StSync
        assert sm.run_until(lambda: len(sm.transition_log) == 4, TIMEOUT_S)
    assert [r.key() for r in sm.transition_log] == [
        ("StSync", "StQuick", "DEFAULT"), ("StQuick", "StReport", "SUCCESS"),
        ("StReport", "StRaise", "SUCCESS"), ("StRaise", "StSync", "ABORT"),
    ]
    assert "CbRaises.on_entry raised" in caplog.text and "boom" in caplog.text


def test_async_behavior_is_cancelled_cooperatively_on_exit(caplog: pytest.LogCaptureFixture) -> None:
    sm = SmWork()
    sm.start()
    sm.post_event(EvB)
    sm.process_events()
    behavior = sm.current_state.get_client_behavior(OrWork, CbCooperative)
    assert behavior.started.wait(TIMEOUT_S)
    assert not behavior.is_shutdown_requested()
    with caplog.at_level(logging.ERROR, logger="smacc_py"):
        sm.post_event(EvGo)
        sm.process_events()
    assert _in(sm, "StSync")
    assert behavior.is_shutdown_requested() and behavior.saw_shutdown and behavior.finished_before_exit
    assert "did not return" not in caplog.text


def test_stuck_async_behavior_cannot_wedge_the_transition(caplog: pytest.LogCaptureFixture) -> None:
    recorder = Recorder()
    sm = SmWork()
    sm.add_observer(recorder)
    sm.start()
    RELEASE_STUCK.clear()
    sm.post_event(EvA)
    sm.process_events()
    behavior = sm.current_state.get_client_behavior(OrWork, CbStuck)
    assert behavior.started.wait(TIMEOUT_S)
    try:
        with caplog.at_level(logging.ERROR, logger="smacc_py"):
            sm.post_event(EvGo)
            sm.process_events()
        assert _in(sm, "StSync")
        assert "CbStuck.on_entry did not return within 0.050 s" in caplog.text
    finally:
        RELEASE_STUCK.set()
    behavior._thread.join(TIMEOUT_S)
    assert not behavior._thread.is_alive()
    # its automatic EvCbFinished arrives after the state exited: CURRENT_STATE drops it
    assert EvCbFinished[CbStuck, OrWork] in recorder.dropped
    assert sm.process_events() == 0 and _in(sm, "StSync")


def test_events_of_an_exited_state_are_dropped_even_if_already_queued() -> None:
    recorder = Recorder()
    sm = SmWork()
    sm.add_observer(recorder)
    sm.start()
    behavior = CbSync.instances[-1]
    sm.post_event(EvB)                 # leaves StSync
    behavior.post_event(EvGo)          # queued while StSync is still active, CURRENT_STATE
    sm.process_events()
    assert _in(sm, "StCoop")           # EvGo would have moved StCoop → StSync had it not been dropped
    behavior.post_event(EvGo)          # posted after exit: dropped at once, never queued
    assert recorder.dropped == [EvGo, EvGo] and recorder.posted.count(EvGo) == 1
    sm.post_event(EvGo)
    sm.process_events()
    assert _in(sm, "StSync")


def test_update_polls_updatables_respecting_their_period_on_the_injected_clock() -> None:
    clock = [0.0]
    sm = SmWork(now=lambda: clock[0])
    sm.start()
    client = sm.requires_client(ClWork)
    client.set_update_period(1.0)
    for t in (0.0, 0.5, 1.0, 1.5, 2.2):
        clock[0] = t
        sm.update()
    assert client.updates == [0.0, 1.0, 2.2]
    with pytest.raises(ValueError, match="update period must be > 0 s"):
        client.set_update_period(0.0)


def test_threaded_mode_runs_on_its_own_worker() -> None:
    entered = threading.Event()
    threads: list[str] = []

    class Watch(SmaccObserver):
        def on_state_entered(self, sm: SmaccStateMachineBase, state: SmaccState) -> None:
            threads.append(threading.current_thread().name)
            if type(state) is StCoop:
                entered.set()

    sm = SmWork()
    sm.add_observer(Watch())
    sm.start(threaded=True)
    try:
        sm.post_event(EvB)
        assert entered.wait(TIMEOUT_S)
        with pytest.raises(Exception, match="not allowed while the worker thread runs"):
            sm.process_events()
    finally:
        sm.stop()
    assert set(threads) == {"SmWork.events"} and sm.current_state_names() == []


# ----------------------------------------------------------------------------- state reactors
class SmReact(SmaccStateMachineBase):
    initial_state = "StAll"


class StAll(SmaccState, parent=SmReact):
    reactions = [Transition(EvAllGo[SrAllEventsGo, "StAll"], "StCond")]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_state_reactor(SrAllEventsGo, EvAllGo[SrAllEventsGo, "StAll"], [EvA, EvB])


class StCond(SmaccState, parent=SmReact):
    reactions = [Transition(EvConditionalTrue[SrConditional, "StCond"], "StCount")]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_state_reactor(SrConditional, EvConditionalTrue[SrConditional, "StCond"], [EvValue],
                                        lambda ev: ev.value > 10)


class StCount(SmaccState, parent=SmReact):
    reactions = [Transition(EvCountdownEnd[SrEventCountdown, "StCount"], "StGen")]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_state_reactor(SrEventCountdown, EvCountdownEnd[SrEventCountdown, "StCount"],
                                        [EvA], 3)


FLAG = {"ready": False}


class StGen(SmaccState, parent=SmReact):
    reactions = [Transition(EvTrue[EgConditionalGenerator, "StGen"], "StOneShot")]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_event_generator(EgConditionalGenerator, ConditionalGeneratorMode.ON_UPDATE,
                                          lambda: FLAG["ready"])


class StOneShot(SmaccState, parent=SmReact):
    reactions = [Transition(EvTrue[EgConditionalGenerator, "StOneShot"], "StEnd")]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_event_generator(EgConditionalGenerator, ConditionalGeneratorMode.ONE_SHOT,
                                          lambda: True)


class StEnd(SmaccState, parent=SmReact):
    pass


def test_reactors_and_generators_drive_transitions() -> None:
    recorder = Recorder()
    sm = SmReact()
    sm.add_observer(recorder)
    sm.start()
    for event in (EvA, EvA):
        sm.post_event(event)
    sm.process_events()
    assert sm.current_state_names() == ["StAll"]
    sm.post_event(EvB)  # SrAllEventsGo: both seen; its output is queued ahead of EvB
    assert recorder.posted[-2:] == [EvAllGo[SrAllEventsGo, StAll], EvB]
    sm.process_events()
    assert sm.current_state_names() == ["StCond"]
    sm.post_event(EvValue(value=3))
    sm.process_events()
    assert sm.current_state_names() == ["StCond"]
    sm.post_event(EvValue(value=12))
    sm.process_events()
    assert sm.current_state_names() == ["StCount"]
    sm.post_event(EvA)
    sm.post_event(EvA)
    sm.process_events()
    assert sm.current_state.get_state_reactor(SrEventCountdown).remaining == 1
    sm.post_event(EvA)
    sm.process_events()
    assert sm.current_state_names() == ["StGen"]
    FLAG["ready"] = False
    sm.update()
    sm.process_events()
    assert recorder.posted[-1] is EvFalse[EgConditionalGenerator, StGen]
    FLAG["ready"] = True
    sm.update()
    sm.process_events()  # StGen → StOneShot, whose ONE_SHOT generator fires on entry → StEnd
    assert [r.key()[1] for r in sm.transition_log] == ["StCond", "StCount", "StGen", "StOneShot", "StEnd"]
