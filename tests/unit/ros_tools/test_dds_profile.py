"""The suite's DDS settings (ros_tools.dds): set where unset, never over the user's choice, and a
Fast DDS profile that this Fast DDS parses (a profile it rejects would silently fall back to the
3 s discovery announcements the profile exists to avoid)."""

from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

from ros_tools.dds import FASTDDS_PROFILE, PROFILE_VARIABLE, keep_dds_local

NS = {"p": "http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"}
PARTICIPANT = """
import rclpy
rclpy.init()
node = rclpy.create_node("dds_profile_probe")
node.destroy_node()
rclpy.shutdown()
print("participant created")
"""


def test_defaults_fill_only_what_the_user_left_unset() -> None:
    env: dict[str, str] = {}
    keep_dds_local(env)
    assert env == {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", PROFILE_VARIABLE: str(FASTDDS_PROFILE)}

    chosen = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "SUBNET", PROFILE_VARIABLE: "/etc/my_profile.xml"}
    keep_dds_local(chosen)
    assert chosen == {"ROS_AUTOMATIC_DISCOVERY_RANGE": "SUBNET", PROFILE_VARIABLE: "/etc/my_profile.xml"}


def test_profile_is_the_default_participant_profile_with_faster_announcements() -> None:
    root = ElementTree.parse(FASTDDS_PROFILE).getroot()
    participant = root.find("p:participant", NS)
    assert participant is not None and participant.get("is_default_profile") == "true"
    discovery = participant.find("p:rtps/p:builtin/p:discovery_config", NS)
    assert discovery is not None
    assert int(discovery.findtext("p:initialAnnouncements/p:count", namespaces=NS) or 0) > 5  # Fast DDS: 5
    lease_s = int(discovery.findtext("p:leaseAnnouncement/p:sec", namespaces=NS) or 99)
    assert lease_s < 3  # Fast DDS: 3 s


def _create_participant(profile: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, PROFILE_VARIABLE: str(profile)}
    return subprocess.run([sys.executable, "-c", PARTICIPANT], env=env, capture_output=True, text=True,
                          timeout=60, cwd=tmp_path)


def test_fast_dds_parses_the_profile(tmp_path: Path) -> None:
    run = _create_participant(FASTDDS_PROFILE, tmp_path)
    assert run.returncode == 0 and "participant created" in run.stdout, run.stderr
    assert "XMLPARSER" not in run.stdout + run.stderr, run.stdout + run.stderr


def test_a_profile_fast_dds_rejects_shows_as_a_parser_error(tmp_path: Path) -> None:
    """The check above can fail: a wrong value is reported by Fast DDS's XML parser."""
    broken = tmp_path / "broken.xml"
    broken.write_text(FASTDDS_PROFILE.read_text().replace("<count>30</count>", "<count>thirty</count>"))
    run = _create_participant(broken, tmp_path)
    assert "XMLPARSER" in run.stdout + run.stderr  # Fast DDS logs to stdout
