"""The cl_nav2z behavior outcomes sm_dance_bot's states react to, named once:
``EvCbSuccess`` / ``EvCbFailure`` of each motion behavior on OrNavigation."""

from __future__ import annotations

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbNavigateForward, CbRotate, CbUndoPathBackwards
from smacc_py.core import EvCbFailure, EvCbSuccess, SmaccEvent
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrNavigation

ABS_ROTATE_OK: type[SmaccEvent] = EvCbSuccess[CbAbsoluteRotate, OrNavigation]
ABS_ROTATE_FAILED: type[SmaccEvent] = EvCbFailure[CbAbsoluteRotate, OrNavigation]
ROTATE_OK: type[SmaccEvent] = EvCbSuccess[CbRotate, OrNavigation]
ROTATE_FAILED: type[SmaccEvent] = EvCbFailure[CbRotate, OrNavigation]
FORWARD_OK: type[SmaccEvent] = EvCbSuccess[CbNavigateForward, OrNavigation]
FORWARD_FAILED: type[SmaccEvent] = EvCbFailure[CbNavigateForward, OrNavigation]
UNDO_OK: type[SmaccEvent] = EvCbSuccess[CbUndoPathBackwards, OrNavigation]
UNDO_FAILED: type[SmaccEvent] = EvCbFailure[CbUndoPathBackwards, OrNavigation]
