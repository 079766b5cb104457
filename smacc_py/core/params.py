"""Engine parameters: one frozen dataclass, defaults in one place."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SmaccEngineParams:
    """Knobs of the core engine (SMACC2 reads the same knobs as node parameters; it has no such class).

    Attributes:
        async_join_timeout_s: how long (s) a state exit waits for an async behavior's ``on_entry`` to
            return after requesting shutdown before logging an error and continuing (SMACC2 waits forever).
        transition_log_size: transitions kept in ``transition_log`` (the ``transition_log_history``
            service answers from it); older ones are discarded.
        signal_detector_loop_freq: rate (Hz) at which the runtime should call ``update()``; SMACC2's
            parameter of the same name, default 20 Hz.
    """

    async_join_timeout_s: float = 5.0
    transition_log_size: int = 10_000
    signal_detector_loop_freq: float = 20.0

    def __post_init__(self) -> None:
        checks = (
            ("async_join_timeout_s", self.async_join_timeout_s >= 0.0, ">= 0 s"),
            ("transition_log_size", self.transition_log_size >= 1, ">= 1"),
            ("signal_detector_loop_freq", self.signal_detector_loop_freq > 0.0, "> 0 Hz"),
        )
        for field_name, ok, rule in checks:
            if not ok:
                raise ValueError(f"SmaccEngineParams.{field_name} must be {rule}, got "
                                 f"{getattr(self, field_name)!r}")
