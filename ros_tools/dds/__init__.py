"""DDS settings every process of the suite runs with, unless the user chose their own.

* ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``: DDS stays on this machine (ROS 2 Jazzy's own variable;
  ``SUBNET`` spans machines, see the README).
* ``FASTRTPS_DEFAULT_PROFILES_FILE``: the suite's Fast DDS profile (``fastdds_profile.xml`` beside this
  module), which announces a new participant more often so that processes find each other in
  milliseconds instead of waiting up to 3 s for Fast DDS's periodic announcement (the file says why).

Call :func:`keep_dds_local` before the process initialises rclpy: Fast DDS reads both once, when
the first participant is created. Child processes inherit them through the environment.
"""

from __future__ import annotations

import os
from collections.abc import MutableMapping
from pathlib import Path

FASTDDS_PROFILE = Path(__file__).with_name("fastdds_profile.xml")
PROFILE_VARIABLE = "FASTRTPS_DEFAULT_PROFILES_FILE"  # the name Fast DDS 2.14 (Jazzy) reads


def keep_dds_local(env: MutableMapping[str, str] | None = None) -> None:
    """Set the suite's DDS defaults in ``env`` (default: this process's environment) where unset."""
    target = os.environ if env is None else env
    target.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    target.setdefault(PROFILE_VARIABLE, str(FASTDDS_PROFILE))
