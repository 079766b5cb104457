"""Throughput and latency of the smacc_py core engine (no ROS).

Machines:
* ping-pong, like SMACC2's sm_coretest_transition_speed_1: two states, each posts
  ``EvStateRequestFinish[Self]`` on entry and transitions to the other on it, so every event is one full
  transition (tag hook lookup, transition record, exit, entry);
* the same with three orthogonals each running a sync behavior per state (behavior build, runtime
  configure, entry, exit, orthogonal slot push/pop), closer to a real mission state;
* unhandled events: post + dispatch of an event no state reacts to (the pure dispatch path).

Latency is measured in the threaded mode: a test thread posts, the worker thread dispatches and enters
the next state, an observer signals back; the figure is post → target entered.

Run: ``.venv/bin/python -m bench.bench_smacc_core`` (``--no-record`` to skip RESULTS.md).
"""

from __future__ import annotations

import statistics
import threading
import time

from bench.harness import Benchmark, parse_cli
from smacc_py.core import (
    EvStateRequestFinish,
    Orthogonal,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)

BATCH = 20_000


class SmPingPong(SmaccStateMachineBase):
    initial_state = "StState1"


class StState1(SmaccState, parent=SmPingPong):
    reactions = (Transition(EvStateRequestFinish["StState1"], "StState2"),)

    def on_entry(self) -> None:
        self.request_finish()


class StState2(SmaccState, parent=SmPingPong):
    reactions = (Transition(EvStateRequestFinish["StState2"], "StState1"),)

    def on_entry(self) -> None:
        self.request_finish()


class OrA(Orthogonal):
    pass


class OrB(Orthogonal):
    pass


class OrC(Orthogonal):
    pass


class CbNoop(SmaccClientBehavior):
    pass


class SmBusy(SmaccStateMachineBase):
    initial_state = "StBusy1"

    def on_initialize(self) -> None:
        for orthogonal in (OrA, OrB, OrC):
            self.create_orthogonal(orthogonal)


class StBusy1(SmaccState, parent=SmBusy):
    reactions = (Transition(EvStateRequestFinish["StBusy1"], "StBusy2"),)

    @classmethod
    def static_configure(cls) -> None:
        for orthogonal in (OrA, OrB, OrC):
            cls.configure_orthogonal(orthogonal, CbNoop)

    def on_entry(self) -> None:
        self.request_finish()


class StBusy2(StBusy1, parent=SmBusy):
    reactions = (Transition(EvStateRequestFinish["StBusy2"], "StBusy1"),)


class EvNoop(SmaccEvent):
    pass


class EvFlip(SmaccEvent):
    pass


class SmManual(SmaccStateMachineBase):
    initial_state = "StManual1"


class StManual1(SmaccState, parent=SmManual):
    reactions = (Transition(EvFlip, "StManual2"),)


class StManual2(SmaccState, parent=SmManual):
    reactions = (Transition(EvFlip, "StManual1"),)


def _rate(bench: Benchmark, label: str, sm: SmaccStateMachineBase, post: bool) -> float:
    def run() -> None:
        if post:
            for _ in range(BATCH):
                sm.post_event(EvNoop)
        sm.process_events(BATCH)

    stats = bench.time(f"{label} ({BATCH} events)", run, repeat=15, warmup=2)
    rate = BATCH / stats.median
    bench.record_value(f"{label}: events dispatched", rate, "events/s", note=f"median of 15 x {BATCH}")
    return rate


def _threaded_latency(bench: Benchmark, samples: int = 300) -> None:
    entered = threading.Event()

    class Signal(SmaccObserver):
        def on_state_entered(self, sm: SmaccStateMachineBase, state: SmaccState) -> None:
            entered.set()

    sm = SmManual()
    sm.add_observer(Signal())
    sm.start(threaded=True)
    latencies: list[float] = []
    try:
        if not entered.wait(5.0):
            raise RuntimeError("worker did not enter the initial state")
        for _ in range(samples):
            entered.clear()
            started = time.perf_counter()
            sm.post_event(EvFlip)
            if not entered.wait(5.0):
                raise RuntimeError("transition did not complete within 5 s")
            latencies.append(time.perf_counter() - started)
    finally:
        sm.stop()
    median_us = statistics.median(latencies) * 1e6
    spread = f"min {min(latencies) * 1e6:.1f}, max {max(latencies) * 1e6:.1f}"
    bench.record_value("threaded transition latency (post → entered)", median_us, "us",
                       note=f"median of {samples}; {spread}")


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("smacc_core")
    ping = SmPingPong(name="SmPingPong")
    ping.start()
    rate = _rate(bench, "ping-pong transitions (sm_coretest_transition_speed_1)", ping, post=False)
    bench.record_value("ping-pong sync transition latency", 1e6 / rate, "us", note="1 / rate")
    busy = SmBusy()
    busy.start()
    _rate(bench, "transitions with 3 orthogonals x 1 sync behavior", busy, post=False)
    idle = SmManual()
    idle.start()  # StManual1 ignores EvNoop
    _rate(bench, "unhandled events (post + dispatch)", idle, post=True)
    _threaded_latency(bench)
    print(f"smacc_core: target >= 50000 events/s in the core: {'met' if rate >= 50_000 else 'NOT met'}")
    bench.save()


if __name__ == "__main__":
    main()
