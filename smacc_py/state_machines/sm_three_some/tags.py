"""The transition tags every state of upstream's sm_three_some declares for itself
(``struct TIMEOUT : ABORT {}`` ...); one set here, as the names are what introspection reports."""

from __future__ import annotations

from smacc_py.core import ABORT, SUCCESS


class TIMEOUT(ABORT):
    """The state's countdown ran out."""


class NEXT(SUCCESS):
    """Key ``n`` (or a sensor message in StState1)."""


class PREVIOUS(ABORT):
    """Key ``p``."""
