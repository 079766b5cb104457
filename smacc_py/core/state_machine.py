"""``SmaccStateMachineBase``: one FIFO event queue, run-to-completion dispatch, hierarchical transitions.

Dispatch semantics (Boost.Statechart as used by SMACC2): events are processed one at a time in posting
order; for each, the reactions of the innermost active state are tried first, then its ancestors'; the
first transition in declaration order whose event matches (by subclass) and whose guard accepts the
event wins; events nobody handles are logged at DEBUG and reported to observers. A transition calls the
reacting state's ``on_exit_<TAG>``, records the transition, exits states innermost-first up to the
innermost common context of source and target, then enters down to the target (and its inner initial
states, or the remembered leaf for ``History``). Self-transitions exit and re-enter.

Events posted by behaviors, reactors and generators carry the sequence number of the state instance
that owns them (CURRENT_STATE lifetime) and are dropped once that instance has begun to exit.

Three mixins this class inherits hold what is not dispatch: ``MachineAssembly`` (``assembly.py``) builds
the orthogonals, clients and components (and their substitutes) once before the first state,
``StateMachineQueries`` (``state_machine_queries.py``) answers read-only lookups (active states,
orthogonals, clients, components, blackboard reads, ``describe``), and ``ObserverRegistry``
(``observer.py``) keeps the observers and calls them. Entering and leaving one state is ``lifecycle.py``.

Two ways to run it:

* synchronously (``start()``, ``post_event()``, ``process_events()``): the caller's thread dispatches.
  Unit tests drive it by hand; the ROS runtime dispatches on its executor thread, so every callback,
  transition and hook of a machine runs on one thread, in an order that does not depend on machine
  load. ``post_event`` is safe from any thread (async behaviors post from their own): the queue and
  the reactor notification are guarded by one lock, and the callback given to ``set_wake_callback``
  (the runtime's "schedule a dispatch on the executor") is called after each post.
* with a worker thread (``start(threaded=True)``) that dispatches as events arrive.

A runtime also calls ``update()`` at ``signal_detector_loop_freq`` and may inject a clock (``now``) so
sim time works.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

from smacc_py.core.assembly import MachineAssembly, StandInFactory, check_substitutes
from smacc_py.core.declared_names import register_machine
from smacc_py.core.errors import InvalidDefinitionError, SmaccError
from smacc_py.core.events import SmaccEvent
from smacc_py.core.global_data import GlobalData
from smacc_py.core.lifecycle import enter_state, exit_state
from smacc_py.core.model import MachineModel, TransitionPlan, compile_model
from smacc_py.core.observer import ObserverRegistry, SmaccObserver, TransitionRecord
from smacc_py.core.orthogonal import Orthogonal
from smacc_py.core.params import SmaccEngineParams
from smacc_py.core.ports import SmaccLogger
from smacc_py.core.reactors import StateReactor
from smacc_py.core.state import SmaccState
from smacc_py.core.state_machine_queries import StateMachineQueries
from smacc_py.core.updatable import poll_updatables

_log = logging.getLogger("smacc_py")


class SmaccStateMachineBase(MachineAssembly, StateMachineQueries, ObserverRegistry):
    """Base of every machine (``smacc2::SmaccStateMachineBase<Derived, InitialState>``): set
    ``initial_state`` and create orthogonals in ``on_initialize``."""

    _is_smacc_state_machine: ClassVar[bool] = True
    initial_state: ClassVar[type[SmaccState] | str]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        register_machine(cls)
        initial = cls.__dict__.get("initial_state")
        if initial is not None and not isinstance(initial, str) and not (
            isinstance(initial, type) and issubclass(initial, SmaccState)
        ):
            raise InvalidDefinitionError(f"{cls.__name__}.initial_state must be a SmaccState class or its "
                                         f"name, got {initial!r}")

    @classmethod
    def validate(cls) -> MachineModel:
        """Compile and validate the declarations now (raises InvalidDefinitionError naming the culprit)."""
        return compile_model(cls)

    def __init__(self, *, params: SmaccEngineParams | None = None, now: Callable[[], float] | None = None,
                 name: str | None = None, substitutes: Mapping[type, StandInFactory] | None = None) -> None:
        """``now``: the clock (s; the ROS runtime injects the node clock). ``substitutes``: stand-ins for
        client and component types, e.g. scripted fakes in unit tests (see ``assembly.py``)."""
        self.params = params or SmaccEngineParams()
        self.name = name or type(self).__name__
        self.model = compile_model(type(self))
        self.substitutes = check_substitutes(substitutes)
        self._now = now or time.monotonic
        self._queue: deque[tuple[SmaccEvent, int | None]] = deque()
        self._post_lock = threading.RLock()
        self._sm_lock = threading.RLock()
        self._wake = threading.Event()
        self._stack: list[SmaccState] = []
        self._active_seqs: set[int] = set()
        self._seq = 0
        self._reactors: tuple[StateReactor, ...] = ()
        self._history: dict[type[SmaccState], type[SmaccState]] = {}
        self._orthogonals: dict[type[Orthogonal], Orthogonal] = {}
        self._orthogonal_list: list[Orthogonal] = []
        self._observers: tuple[SmaccObserver, ...] = ()
        self._table: dict[type[SmaccEvent], tuple[TransitionPlan, ...]] = {}
        self._transition_count = 0
        self._initialized = False
        self._running = False
        self._worker: threading.Thread | None = None
        self._stop_requested = False
        self._wake_needed = False  # True while a worker or run_until() waits for posts
        self._wake_callback: Callable[[], None] | None = None  # called after each post
        self._dispatch_thread: int | None = None  # the thread inside _drain: it must not re-enter it
        self.global_data = GlobalData()
        self._logger: SmaccLogger = logging.getLogger(f"smacc_py.{self.name}")
        self.transition_log: deque[TransitionRecord] = deque(maxlen=self.params.transition_log_size)

    # ------------------------------------------------------------------ running
    def start(self, *, threaded: bool = False) -> None:
        """Initialise and enter the initial configuration; with ``threaded`` a worker thread does it."""
        if self._running:
            raise SmaccError(f"{self.name} is already running")
        self.initialize()
        self._running = True
        self._stop_requested = False
        if threaded:
            self._wake_needed = True
            self._worker = threading.Thread(target=self._worker_main, name=f"{self.name}.events", daemon=True)
            self._worker.start()
        else:
            with self._sm_lock:
                self._enter_path(self.model.initial_path)

    def stop(self, timeout_s: float = 5.0) -> None:
        """Stop the worker (if any, waiting up to ``timeout_s``) and exit every active state."""
        worker = self._worker
        if worker is not None:
            self._stop_requested = True
            self._wake.set()
            if worker is not threading.current_thread():
                worker.join(timeout_s)
                if worker.is_alive():
                    _log.error("%s: event thread did not stop within %.1f s", self.name, timeout_s)
            self._worker = None
            self._wake_needed = False
        with self._sm_lock:
            self._exit_to(0)
        self._running = False

    def _worker_main(self) -> None:
        with self._sm_lock:
            self._enter_path(self.model.initial_path)
        while not self._stop_requested:
            self._wake.wait()
            self._wake.clear()
            if not self._stop_requested:
                self._drain(None)

    def post_event(self, event: SmaccEvent | type[SmaccEvent], *, owner_seq: int | None = None) -> None:
        """Queue an event (class or instance) from any thread; reactors of active states see it first.

        ``owner_seq`` gives CURRENT_STATE lifetime: the event is dropped if the state instance with that
        sequence number has begun to exit (now or by the time the event is dispatched).
        """
        if isinstance(event, type):
            event = event()
        if owner_seq is not None and owner_seq not in self._active_seqs:
            self._dropped(event)
            return
        with self._post_lock:  # reactors see events in the order the queue holds them
            for reactor in self._reactors:
                if isinstance(event, reactor.input_events):
                    try:
                        reactor._notify(event)
                    except Exception:
                        _log.exception("%s.on_event_notified raised; skipped", type(reactor).__name__)
            self._queue.append((event, owner_seq))
        if self._observers:
            self._notify(SmaccObserver.on_event_posted, event)
        if self._wake_needed:
            self._wake.set()
        wake = self._wake_callback
        if wake is not None:
            try:
                wake()
            except Exception:
                _log.exception("%s: the wake callback raised; the event stays queued", self.name)

    def set_wake_callback(self, callback: Callable[[], None] | None) -> None:
        """Call ``callback()`` after every post, on the posting thread (None: stop calling).

        For a runtime that dispatches synchronously on a thread of its own (the ROS runtime's executor):
        the callback schedules ``process_events()`` there. It must be quick and must not dispatch itself.
        """
        self._wake_callback = callback

    def process_events(self, max_events: int | None = None) -> int:
        """Dispatch queued events (and those they cause) until the queue is empty; returns the count.

        For synchronous use only; raises SmaccError while a worker thread owns the queue.
        """
        if self._worker is not None:
            raise SmaccError(f"{self.name}: process_events() is not allowed while the worker thread runs")
        if not self._running:
            raise SmaccError(f"{self.name}: start() the machine before processing events")
        if self._dispatch_thread == threading.get_ident():
            raise SmaccError(f"{self.name}: process_events() called from inside a dispatch (a hook or an "
                             "observer); post the event instead, the running dispatch will handle it")
        return self._drain(max_events)

    def run_until(self, predicate: Callable[[], bool], timeout_s: float) -> bool:
        """Synchronous mode: process events, waiting for more (e.g. from async behaviors), until
        ``predicate()`` holds or ``timeout_s`` (wall-clock s) passes; returns ``predicate()``."""
        deadline = time.monotonic() + timeout_s
        self._wake_needed = True
        try:
            while True:
                self._wake.clear()
                self.process_events()
                if predicate():
                    return True
                remaining = deadline - time.monotonic()
                if remaining <= 0.0:
                    return predicate()
                self._wake.wait(remaining)
        finally:
            self._wake_needed = False

    def _drain(self, max_events: int | None) -> int:
        with self._sm_lock:
            self._dispatch_thread = threading.get_ident()
            try:
                return self._dispatch_queued(max_events)
            finally:
                self._dispatch_thread = None

    def _dispatch_queued(self, max_events: int | None) -> int:
        queue = self._queue
        popleft = queue.popleft
        active = self._active_seqs
        count = 0
        while queue:
            if max_events is not None and count >= max_events:
                break
            event, seq = popleft()
            count += 1
            if seq is not None and seq not in active:
                self._dropped(event)
                continue
            event_type = type(event)
            plans = self._table.get(event_type)
            if plans is None:
                plans = self.model.candidates(type(self._stack[-1]), event_type)
                self._table[event_type] = plans
            for plan in plans:
                guard = plan.guard
                if guard is not None:
                    try:
                        if not guard(event):
                            continue
                    except Exception:
                        _log.exception("guard of %r raised on %r; treated as false", plan.transition, event)
                        continue
                self._transit(plan, event)
                break
            else:
                _log.debug("%s: unhandled event %r in %s", self.name, event, self._leaf_name())
                if self._observers:
                    self._notify(SmaccObserver.on_event_unhandled, event)
        return count

    # ------------------------------------------------------------------ transitions
    def _transit(self, plan: TransitionPlan, event: SmaccEvent) -> None:
        if plan.tag_hook is not None:
            try:
                plan.tag_hook(self._stack[plan.source_level])
            except Exception:
                _log.exception("%s.on_exit_%s raised; skipped", plan.source.__name__, plan.tag.__name__)
        path = plan.entry_path
        if plan.history:
            path = self.model.history_path(plan, self._history.get(plan.target))
        self._transition_count += 1
        record = TransitionRecord(self._transition_count, plan.source, plan.target, path[-1], plan.tag,
                                  event, plan.history, self._now())
        self.transition_log.append(record)
        if self._observers:
            self._notify(SmaccObserver.on_transition, record)
        self._exit_to(plan.keep_depth)
        self._enter_path(path)

    def _exit_to(self, keep: int) -> None:
        stack = self._stack
        if len(stack) <= keep:
            return
        leaf = type(stack[-1])
        for state in stack[keep:]:
            self._active_seqs.discard(state.seq)
        superstates = self.model.superstates
        while len(stack) > keep:
            state = stack[-1]
            if type(state) in superstates:
                self._history[type(state)] = leaf
            exit_state(self, state)
        if not stack:
            self._table = {}

    def _enter_path(self, path: tuple[type[SmaccState], ...]) -> None:
        for cls in path:
            enter_state(self, cls)
        self._table = self.model.table_for(type(self._stack[-1]))

    # ------------------------------------------------------------------ polling, clock, observers
    def get_logger(self) -> SmaccLogger:
        """The machine's logger: ``logging.getLogger("smacc_py.<name>")``, or what ``set_logger`` gave (the
        ROS runtime gives the node's logger, as SMACC2's ``getLogger()``)."""
        return self._logger

    getLogger = get_logger  # SMACC2's spelling

    def set_logger(self, logger: SmaccLogger) -> None:
        """Log through ``logger`` from now on (every ``get_logger()`` asks the machine)."""
        self._logger = logger

    def now(self) -> float:
        """The injected clock (s); ``time.monotonic`` unless the runtime passed ``now=``."""
        return self._now()

    def update(self) -> None:
        """Poll every ISmaccUpdatable client, component, and active behavior, reactor and generator."""
        with self._sm_lock:
            objects: list[object] = []
            for orthogonal in self._orthogonal_list:
                for client in orthogonal.clients:
                    objects.append(client)
                    objects.extend(client.components)
            for state in self._stack:
                objects.extend(b for _, b in state.behaviors)
                objects.extend(state.reactors)
                objects.extend(state.generators)
        poll_updatables(objects, self._now(), self._active_seqs)

    def _dropped(self, event: SmaccEvent) -> None:
        _log.debug("%s: dropped %r: the state that posted it has exited", self.name, event)
        if self._observers:
            self._notify(SmaccObserver.on_event_dropped, event)

    # ------------------------------------------------------------------ blackboard
    def set_global_sm_data(self, name: str, value: Any) -> None:
        """Store a named value on the machine's blackboard."""
        self.global_data.set(name, value)
