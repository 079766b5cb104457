"""The count the conftest's participant warning reads (tests/helpers/dds_participants.py)."""

from __future__ import annotations

import os

import pytest
import rclpy
from rclpy.context import Context
from rclpy.node import Node

from tests.helpers.dds_participants import own_participants

pytestmark = pytest.mark.ros


def test_a_context_with_a_node_adds_one_participant_and_its_end_removes_it() -> None:
    domain = int(os.environ["ROS_DOMAIN_ID"])
    before = own_participants(domain)
    context = Context()
    rclpy.init(context=context)
    node = Node("participant_count_probe", context=context)
    try:
        assert own_participants(domain) == before + 1
        assert own_participants((domain + 1) % 100) == 0  # another domain's ports are not ours
    finally:
        node.destroy_node()
        rclpy.shutdown(context=context)
    assert own_participants(domain) == before
