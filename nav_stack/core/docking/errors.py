"""DockRobot / UndockRobot result codes, feedback states and the failures that carry them.

Codes and states are nav2_msgs (Jazzy) ``DockRobot``/``UndockRobot`` constants. A failure is raised
inside the docking core as a :class:`DockingError` subclass (opennav_docking_core's exception of the
same name) and becomes a result with its code and message; ``retryable`` marks the failures Nav2's
docking loop answers with another attempt from the staging pose (detection lost, control failed,
no charge), as opposed to those that end the goal at once.
"""

from __future__ import annotations

import enum


class DockErrorCode(enum.IntEnum):
    """nav2_msgs/action/DockRobot result codes (UndockRobot uses 902, 905 and 999 of them)."""

    NONE = 0
    DOCK_NOT_IN_DB = 901
    DOCK_NOT_VALID = 902
    FAILED_TO_STAGE = 903
    FAILED_TO_DETECT_DOCK = 904
    FAILED_TO_CONTROL = 905
    FAILED_TO_CHARGE = 906
    UNKNOWN = 999


class DockingState(enum.IntEnum):
    """nav2_msgs/action/DockRobot feedback ``state``."""

    NONE = 0
    NAV_TO_STAGING_POSE = 1
    INITIAL_PERCEPTION = 2
    CONTROLLING = 3
    WAIT_FOR_CHARGE = 4
    RETRY = 5


class DockingError(Exception):
    """A docking failure with its result code; ``str()`` is the message for ``error_msg``."""

    code = DockErrorCode.UNKNOWN
    retryable = False


class DockNotInDB(DockingError):  # noqa: N818 - opennav_docking_core's name
    """The requested dock id is not in the database."""

    code = DockErrorCode.DOCK_NOT_IN_DB


class DockNotValid(DockingError):  # noqa: N818 - opennav_docking_core's name
    """The dock has no usable plugin, or the request describes no valid dock."""

    code = DockErrorCode.DOCK_NOT_VALID


class FailedToStage(DockingError):  # noqa: N818 - opennav_docking_core's name
    """Navigation to the staging pose failed or ran out of ``max_staging_time``."""

    code = DockErrorCode.FAILED_TO_STAGE


class FailedToDetectDock(DockingError):  # noqa: N818 - opennav_docking_core's name
    """No usable dock detection (initially, or lost during the approach: then retried)."""

    code = DockErrorCode.FAILED_TO_DETECT_DOCK
    retryable = True


class FailedToControl(DockingError):  # noqa: N818 - opennav_docking_core's name
    """The approach timed out or a commanded motion would collide (retried during docking)."""

    code = DockErrorCode.FAILED_TO_CONTROL
    retryable = True


class FailedToCharge(DockingError):  # noqa: N818 - opennav_docking_core's name
    """Docked, but charging did not start within ``wait_charge_timeout``."""

    code = DockErrorCode.FAILED_TO_CHARGE
    retryable = True


class FrameUnavailable(Exception):  # noqa: N818 - reads as a condition, like tf2's LookupException
    """A pose could not be expressed in a frame (the world's TF could not tell); the message says why."""
