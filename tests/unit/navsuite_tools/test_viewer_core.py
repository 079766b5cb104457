"""The viewer's ROS-free parts: hub versions and throttle, payload encoding, graph layout, monitors, CLI.

"""

from __future__ import annotations

import base64
import json
import math

import numpy as np
import pytest

from navsuite_tools.viewer import encode
from navsuite_tools.viewer.hub import LayerHub, Throttle
from navsuite_tools.viewer.main import parse_args
from navsuite_tools.viewer.monitors import (
    BtEvent,
    BtMonitor,
    SmaccMonitor,
    StateInfo,
    TransitionInfo,
    layered_layout,
    short_name,
)
from navsuite_tools.viewer.params import ViewerParams


# ---------------------------------------------------------------- hub
def test_hub_sends_each_changed_layer_once_and_skips_unchanged_digests():
    hub, calls = LayerHub(), []

    def producer(value):
        return lambda: calls.append(value) or {"v": value}

    assert hub.publish("map", producer(1), digest="a")
    assert not hub.publish("map", producer(2), digest="a")  # same content: not re-sent
    seen: dict[str, int] = {}
    assert dict(hub.changed(seen)) == {"map": '{"v":1}'}
    assert dict(hub.changed(seen)) == {}
    for value in range(3, 50):  # a burst between two sends costs one conversion, of the newest value
        hub.publish("scan", producer(value))
    assert dict(hub.changed(seen)) == {"scan": '{"v":49}'}
    assert calls == [1, 49]
    assert hub.snapshot() == {"map": {"v": 1}, "scan": {"v": 49}}  # cached text: no new conversion
    assert calls == [1, 49]


def test_hub_turns_a_failing_or_nan_producer_into_an_error_payload():
    hub = LayerHub()
    hub.publish("bad", lambda: 1 / 0)
    hub.publish("nan", lambda: {"x": math.nan})
    state = hub.snapshot()
    assert "ZeroDivisionError" in state["bad"]["error"]
    assert "ValueError" in state["nan"]["error"]


def test_hub_wait_wakes_on_publish_and_on_close():
    hub = LayerHub()
    assert not hub.wait(0, timeout=0.01)
    hub.publish("a", dict)
    assert hub.wait(0, timeout=0.01)
    hub.close()
    assert not hub.wait(hub.version, timeout=5.0)  # returns at once once closed


def test_throttle_spaces_sends_by_the_period():
    now = [100.0]
    throttle = Throttle(10.0, clock=lambda: now[0])
    assert throttle.delay() == 0.0
    throttle.mark()
    now[0] += 0.03
    assert throttle.delay() == pytest.approx(0.07)
    now[0] += 0.2
    assert throttle.delay() == 0.0
    with pytest.raises(ValueError, match="rate must be > 0"):
        Throttle(0.0)


# ---------------------------------------------------------------- encoding
def test_scan_points_keep_valid_returns_and_apply_the_transform():
    ranges = [1.0, math.inf, -math.inf, math.nan, 0.05, 4.0, 2.0]
    angles_step = math.pi / 2
    pts = encode.scan_points(ranges, 0.0, angles_step, 0.1, 3.5, (1.0, 2.0, math.pi))
    # beam 0: (1, 0) → rotated π → (-1, 0) → +(1, 2) = (0, 2); beam 6 at 3π: (-2, 0) → (2, 0) → (3, 2)
    assert pts == pytest.approx([0.0, 2.0, 3.0, 2.0], abs=1e-9)


def test_poses_are_decimated_keeping_the_last_and_wrapped():
    poses = np.column_stack((np.arange(10.0), np.zeros(10), np.full(10, 3.0)))
    out = np.array(encode.poses_payload(poses, (0.0, 0.0, 1.0), limit=4)).reshape(-1, 3)
    assert len(out) == 4
    assert out[-1, 0] == pytest.approx(9 * math.cos(1.0), abs=1e-3)
    assert out[0, 2] == pytest.approx(4.0 - 2 * math.pi, abs=1e-3)


def test_grid_payload_keeps_bytes_and_checks_size():
    data = bytes([0, 100, 255, 42, 7, 0])
    payload = encode.grid_payload(3, 2, 0.05, (1.0, 2.0, 0.0), data, "map")
    assert base64.b64decode(payload["data"]) == data
    with pytest.raises(ValueError, match="expected width\\*height = 4\\*2"):
        encode.grid_payload(4, 2, 0.05, (0.0, 0.0, 0.0), data, "map")
    same = encode.grid_digest(3, 2, 0.05, (1.0, 2.0, 0.0), data)
    assert same == encode.grid_digest(3, 2, 0.05, (1.0, 2.0, 0.0), bytes(data))
    assert same != encode.grid_digest(3, 2, 0.05, (1.0, 2.5, 0.0), data)
    assert encode.finite_or_none(math.nan) is None and encode.finite_or_none(0.5) == 0.5


# ---------------------------------------------------------------- state machines and trees
def test_layered_layout_follows_transitions_from_the_initial_state():
    place = layered_layout(["A", "B", "C", "D", "Lone"], [("A", "B"), ("B", "C"), ("B", "D"), ("C", "B")])
    assert {n: p[0] for n, p in place.items()} == {"A": 0, "B": 1, "C": 2, "D": 2, "Lone": 3}
    assert sorted(place[n][1] for n in ("C", "D")) == [0, 1]


def test_smacc_monitor_matches_short_names_and_counts_only_real_changes():
    sm = SmaccMonitor("/sm_x")
    a_to_b = TransitionInfo("sm_x::StA", "sm_x::StB", "SUCCESS", "", "EvCbSuccess")
    states = [StateInfo("sm_x::StA", 0, (), (a_to_b,)),
              StateInfo("sm_x::StB", 0, (), (TransitionInfo("", "sm_x::StEnd", "ABORT"),))]
    sm.set_description(states)
    sm.set_description(states)  # republished every 0.5 s: no change
    sm.set_status(["sm_x::StA"], {})
    revision = sm.revision
    sm.set_status(["StA"], {})
    assert sm.revision == revision
    sm.add_transition(1.5, TransitionInfo("sm_x::StA", "sm_x::StB", "SUCCESS", "t", "sm_x::EvCbSuccess"))
    snap = sm.snapshot()
    assert [n["id"] for n in snap["nodes"]] == ["StA", "StB", "StEnd"]  # StEnd only appears as a target
    assert [(e["source"], e["target"], e["tag"]) for e in snap["edges"]] == [
        ("StA", "StB", "SUCCESS"), ("StB", "StEnd", "ABORT")]
    assert snap["current"] == ["StA"]
    assert snap["transitions"][-1]["source"] == "StA" and snap["transitions"][-1]["stamp"] == 1.5
    assert short_name("a.b.StFoo") == "StFoo" and short_name("ns::St<ns::X>") == "St<ns::X>"


def test_bt_monitor_keeps_the_last_status_per_node_in_uid_order():
    bt = BtMonitor(history=3)
    bt.apply([BtEvent(0.0, "Root", 1, "IDLE", "RUNNING"), BtEvent(0.0, "Plan", 4, "IDLE", "RUNNING")])
    bt.apply([BtEvent(1.0, "Plan", 4, "RUNNING", "FAILURE"), BtEvent(1.0, "Spin", 2, "IDLE", "RUNNING")])
    snap = bt.snapshot()
    assert [(n["name"], n["status"], n["changes"]) for n in snap["nodes"]] == [
        ("Root", "RUNNING", 1), ("Spin", "RUNNING", 1), ("Plan", "FAILURE", 2)]
    assert len(snap["recent"]) == 3 and snap["batches"] == 2
    bt.set_structure(json.dumps({"name": "Root", "uid": 1, "children": [{"name": "Plan", "uid": 4}]}))
    assert bt.snapshot()["structure"]["children"][0]["name"] == "Plan"
    with pytest.raises(ValueError, match=r"tree.children\[0\] must be an object"):
        bt.set_structure('{"name": "Root", "children": [3]}')
    with pytest.raises(ValueError, match="not JSON"):
        bt.set_structure("{")


# ---------------------------------------------------------------- settings
def test_params_and_command_line():
    params, ros_args = parse_args(["--port", "0", "--rate", "5", "--ros-args", "-r", "/map:=/other"])
    assert (params.port, params.rate, params.host) == (0, 5.0, "127.0.0.1")
    assert ros_args == ["--ros-args", "-r", "/map:=/other"]
    with pytest.raises(ValueError, match="rate must be in"):
        ViewerParams(rate=0.0)
    with pytest.raises(ValueError, match="sim_time must be one of"):
        ViewerParams(sim_time="maybe")
    with pytest.raises(SystemExit) as exc:
        parse_args(["--rate", "-1"])
    assert exc.value.code == 2
