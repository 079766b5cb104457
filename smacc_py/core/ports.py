"""Ports: what the parts of a machine need from the machine and from the state that owns them.

Clients, components, orthogonals, behaviors, reactors, generators and states all hold a reference to
their machine, and behaviors, reactors and generators to their state. Those classes sit *below* the
machine (a state declaration names its orthogonals and behaviors, the machine is built from states), so
they cannot import ``SmaccStateMachineBase`` or ``SmaccState`` without an import cycle. Instead they
type these references with the protocols below, which list exactly what they use. The concrete classes
satisfy them structurally; nothing subclasses them. SMACC2 has the same seam as abstract interfaces
(``smacc2::ISmaccStateMachine``, ``smacc2::ISmaccState``) that its components include instead of the
concrete templates.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, TypeVar

from smacc_py.core.events import SmaccEvent

C = TypeVar("C")


class SmaccLogger(Protocol):
    """What ``get_logger()`` returns: a ``logging.Logger`` without ROS, the node's rclpy logger under the
    ROS runtime (SMACC2's ``getLogger()`` is the node's rclcpp logger). Both take one message string."""

    def debug(self, message: str, /) -> object:
        """Log at DEBUG."""

    def info(self, message: str, /) -> object:
        """Log at INFO."""

    def warning(self, message: str, /) -> object:
        """Log at WARN."""

    def error(self, message: str, /) -> object:
        """Log at ERROR."""

    def fatal(self, message: str, /) -> object:
        """Log at FATAL (``logging``'s CRITICAL)."""


class MachinePort(Protocol):
    """What parts and states ask of their machine (``smacc2::ISmaccStateMachine``).

    ``SmaccStateMachineBase`` implements it; a part that needs more (the transition log, observers)
    belongs to the runtime, which holds the concrete machine.
    """

    @property
    def name(self) -> str:
        """The machine's name (its class name unless given)."""

    @property
    def is_initialized(self) -> bool:
        """True once orthogonals, clients and components exist."""

    def now(self) -> float:
        """The machine clock (s): the node clock under the ROS runtime, so sim time works."""

    def get_logger(self) -> SmaccLogger:
        """The machine's logger (the node's under the ROS runtime)."""

    def post_event(self, event: SmaccEvent | type[SmaccEvent], *, owner_seq: int | None = None) -> None:
        """Queue an event; ``owner_seq`` gives it CURRENT_STATE lifetime."""

    def build_part(self, wanted: type[C], args: tuple[Any, ...], kwargs: Mapping[str, Any]) -> C:
        """``wanted(*args, **kwargs)`` or the stand-in the machine was given for ``wanted``."""

    def get_orthogonal(self, orthogonal_type: type[C]) -> C:
        """The orthogonal of that type; SmaccLookupError when absent."""

    def requires_client(self, client_type: type[C], who: str | None = None) -> C:
        """A client of any orthogonal; SmaccLookupError naming ``who`` when absent."""

    def requires_component(self, component_type: type[C], who: str | None = None) -> C:
        """A component of any client; SmaccLookupError naming ``who`` when absent."""

    def set_global_sm_data(self, name: str, value: Any) -> None:
        """Store a named value on the machine's blackboard."""

    def get_global_sm_data(self, name: str, default: Any = ...) -> Any:
        """Read a named value; ``default`` when given and absent, else SmaccLookupError."""


class StatePort(Protocol):
    """What a behavior, reactor or generator asks of the state instance that owns it
    (``smacc2::ISmaccState``): its machine, and its sequence number, which stamps the events the part
    posts with CURRENT_STATE lifetime. ``SmaccState`` implements it."""

    @property
    def sm(self) -> MachinePort:
        """The machine the state runs in."""

    @property
    def seq(self) -> int:
        """Number of this state instance, unique within its machine."""
