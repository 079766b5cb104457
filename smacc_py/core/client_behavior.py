"""Client behaviors: state-lifetime objects that make an orthogonal's client do something.

* ``SmaccClientBehavior`` (sync): ``on_entry``/``on_exit`` run on the machine thread (under the ROS
  runtime: the executor thread, which also runs every ROS callback) and must return at once: no
  sleep, no wait on a future or an event. Timing comes from node-clock timers or ISmaccUpdatable.
* ``SmaccAsyncClientBehavior``: ``on_entry`` runs in its own thread; when it returns ``EvCbFinished`` is
  posted automatically. On state exit the engine sets the shutdown flag (``is_shutdown_requested``),
  waits at most ``join_timeout_s`` (s) for ``on_entry`` to return, logs an error if it did not, and
  continues, so a behavior that never checks the flag cannot wedge the transition (SMACC2 #530).
  That join holds the machine thread (the executor, under the ROS runtime) while ``on_entry``
  finishes: check ``is_shutdown_requested()`` often, or wait with ``wait_for_shutdown``.

Every event a behavior posts has CURRENT_STATE lifetime: it carries the sequence number of the state
instance that owns the behavior and is dropped once that instance has begun to exit.

Behaviors sit below the orthogonal, the state and the machine (a state declaration names its behavior
classes); they reach those through ``OrthogonalPort``, ``StatePort`` and ``MachinePort``.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Mapping
from typing import Any, TypeVar

from smacc_py.core.client import OrthogonalPort
from smacc_py.core.errors import missing
from smacc_py.core.events import EvCbFailure, EvCbFinished, EvCbSuccess, SmaccEvent
from smacc_py.core.ports import MachinePort, SmaccLogger, StatePort

_log = logging.getLogger("smacc_py")
C = TypeVar("C")


class ISmaccClientBehavior:
    """Common base of sync and async behaviors (``smacc2::ISmaccClientBehavior``). The engine attaches it
    before ``runtime_configure``."""

    orthogonal: OrthogonalPort
    state: StatePort
    sm: MachinePort
    _seq: int

    def _attach(self, orthogonal: OrthogonalPort, state: StatePort) -> None:
        self.orthogonal = orthogonal
        self.state = state
        self.sm = state.sm
        self._seq = state.seq

    # ------------------------------------------------------------------ user hooks
    @classmethod
    def configuration_problem(cls, orthogonal: OrthogonalPort, args: tuple[Any, ...],
                              kwargs: Mapping[str, Any]) -> str | None:
        """Why ``cls(*args, **kwargs)`` cannot work on ``orthogonal`` as the machine created it, or None.

        Called once per ``configure_orthogonal`` when the machine initializes (its clients exist), so a
        configuration that only the clients can judge (a tick count for a timer without a tick period)
        fails at startup with this text, not silently when the state is entered.
        """
        return None

    def runtime_configure(self) -> None:
        """Called after the state's ``runtime_configure`` and before any ``on_entry``."""

    def on_entry(self) -> None:
        """Start the work. Sync behaviors must return at once (they run on the machine thread)."""

    def on_exit(self) -> None:
        """Clean up when the owning state exits (runs on the machine thread; must not block)."""

    # ------------------------------------------------------------------ helpers
    def get_current_state(self) -> StatePort:
        """The state instance that owns this behavior."""
        return self.state

    def get_state_machine(self) -> MachinePort:
        """The machine."""
        return self.sm

    def get_logger(self) -> SmaccLogger:
        """The machine's logger (the node's under the ROS runtime), as SMACC2's ``getLogger()``."""
        return self.sm.get_logger()

    getLogger = get_logger  # SMACC2's spelling

    def requires_client(self, client_type: type[C]) -> C:
        """A client of this behavior's orthogonal; SmaccLookupError naming the orthogonal when absent."""
        found = self.orthogonal.get_client(client_type)
        if found is None:
            raise missing("client", client_type, type(self).__name__, type(self.orthogonal).__name__)
        return found

    def requires_component(self, component_type: type[C]) -> C:
        """A component of any client of any orthogonal (own orthogonal first)."""
        for client in self.orthogonal.clients:
            found = client.get_component(component_type)
            if found is not None:
                return found
        return self.sm.requires_component(component_type, who=type(self).__name__)

    def own_event(self, template: type[SmaccEvent]) -> type[SmaccEvent]:
        """``template[ThisBehavior, ThisOrthogonal]``, e.g. ``EvCbSuccess[CbX, OrY]``."""
        return template[type(self), type(self.orthogonal)]

    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post with CURRENT_STATE lifetime (dropped if the owning state has begun to exit)."""
        self.sm.post_event(event, owner_seq=self._seq)

    def post_success_event(self, **payload: Any) -> None:
        """Post ``EvCbSuccess[ThisBehavior, ThisOrthogonal]`` with an optional payload."""
        self.post_event(self.own_event(EvCbSuccess)(**payload))

    def post_failure_event(self, **payload: Any) -> None:
        """Post ``EvCbFailure[ThisBehavior, ThisOrthogonal]`` with an optional payload."""
        self.post_event(self.own_event(EvCbFailure)(**payload))

    # ------------------------------------------------------------------ engine protocol
    def _engine_entry(self) -> None:
        self.on_entry()

    def _engine_exit(self, default_join_timeout_s: float) -> None:
        self.on_exit()


class SmaccClientBehavior(ISmaccClientBehavior):
    """A synchronous behavior (``smacc2::SmaccClientBehavior``): ``on_entry`` and ``on_exit`` run on the
    machine thread."""


class SmaccAsyncClientBehavior(ISmaccClientBehavior):
    """A behavior whose ``on_entry`` runs in its own thread with cooperative cancellation
    (``smacc2::SmaccAsyncClientBehavior``).

    Attributes:
        join_timeout_s: bound (s) on waiting for ``on_entry`` after the shutdown request; None uses the
            machine's ``SmaccEngineParams.async_join_timeout_s``.
    """

    join_timeout_s: float | None = None
    _shutdown: threading.Event
    _thread: threading.Thread | None = None

    def is_shutdown_requested(self) -> bool:
        """True once the owning state has begun to exit: return from ``on_entry`` soon."""
        return self._shutdown.is_set()

    def wait_for_shutdown(self, timeout_s: float) -> bool:
        """Sleep up to ``timeout_s`` (s) but wake at once on shutdown; returns ``is_shutdown_requested()``."""
        return self._shutdown.wait(timeout_s)

    def is_finished(self) -> bool:
        """True when ``on_entry`` has returned (or was never started)."""
        return self._thread is None or not self._thread.is_alive()

    def _engine_entry(self) -> None:
        self._shutdown = threading.Event()
        self._thread = threading.Thread(
            target=self._run_on_entry, name=f"{type(self).__name__}.on_entry", daemon=True
        )
        self._thread.start()

    def _run_on_entry(self) -> None:
        try:
            self.on_entry()
        except Exception:
            _log.exception("%s.on_entry raised; posting EvCbFailure", type(self).__name__)
            self.post_failure_event()
        self.post_event(self.own_event(EvCbFinished))

    def _engine_exit(self, default_join_timeout_s: float) -> None:
        self._shutdown.set()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            bound = self.join_timeout_s if self.join_timeout_s is not None else default_join_timeout_s
            thread.join(bound)
            if thread.is_alive():
                _log.error(
                    "%s.on_entry did not return within %.3f s of the shutdown request; continuing the "
                    "transition and leaving its thread behind (check is_shutdown_requested() in on_entry)",
                    type(self).__name__, bound,
                )
        self.on_exit()
