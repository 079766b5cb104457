"""The machine's own events (declared in upstream's ``sm_three_some.hpp``), in a module of their own so
that the states can name them without importing the machine."""

from __future__ import annotations

from smacc_py.core import SmaccEvent


class EvToDeep(SmaccEvent):
    """Back to where MsRun was (MsRecover's deep-history transition)."""


class EvFail(SmaccEvent):
    """Leave MsRun for MsRecover (StState1's reaction)."""
