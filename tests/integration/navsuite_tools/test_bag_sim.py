"""navsuite-bag against a live sim2d: record, info, play (with and without /clock), report.

One module-scoped recording of a few sim seconds feeds every test, which keeps the module at
well under a minute.
"""

from __future__ import annotations

import numpy as np
import pytest
from mcap.reader import make_reader
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy
from rosgraph_msgs.msg import Clock

from navsuite_testing.ros import spin_until, start_python, stop_process, wait_until
from navsuite_tools.bag.qos import parse_offered_qos
from navsuite_tools.bag.reader import BagReader
from navsuite_tools.report import ReportParams, write_report
from navsuite_tools.report.render import TRUTH_COLOR
from tests.helpers.bag_replay import BAG_CLI, TopicCounter, bag_info, play_and_count
from tests.helpers.bag_sim import PROCESS_TIMEOUT, record_sim
from tests.helpers.report_pixels import distinct_colors, load_rgb, pixels_near

pytestmark = pytest.mark.ros

SIM_TOPICS = {
    "/scan": "sensor_msgs/msg/LaserScan",
    "/odom": "nav_msgs/msg/Odometry",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/clock": "rosgraph_msgs/msg/Clock",
}
PLAYED = ("/scan", "/odom", "/tf", "/clock", "/tf_static")


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    return record_sim(tmp_path_factory.mktemp("bag_sim") / "sim.mcap")


def _run(*args: str) -> tuple[int, str]:
    proc = start_python(BAG_CLI, list(args))
    try:
        proc.wait(timeout=PROCESS_TIMEOUT)
    finally:
        output = stop_process(proc)
    return proc.returncode, output


def test_info_lists_the_sim_topics_with_counts(recording):
    listed = bag_info(recording.path)
    for topic, type_name in SIM_TOPICS.items():
        assert listed[topic][0] == type_name, listed
        assert listed[topic][1] > 0, listed
    with BagReader(recording.path) as reader:  # sim time: a few seconds, not the wall-clock epoch
        assert {topic: (info.type, info.count) for topic, info in reader.topics.items()} == listed
        assert 2.5 <= reader.duration_ns / 1e9 <= 4.0
        assert reader.start_ns < 1e12


def test_file_is_a_plain_ros2_mcap(recording):
    with recording.path.open("rb") as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        schemas = {s.id: s for s in summary.schemas.values()}
        channels = {c.topic: c for c in summary.channels.values()}
        assert {s.encoding for s in schemas.values()} == {"ros2msg"}
        assert {c.message_encoding for c in channels.values()} == {"cdr"}
        assert schemas[channels["/scan"].schema_id].name == "sensor_msgs/msg/LaserScan"
        assert channels["/scan"].metadata["topic_type_hash"].startswith("RIHS01_")
        (static_qos,) = parse_offered_qos(channels["/tf_static"].metadata["offered_qos_profiles"])
        assert static_qos.durability.name == "TRANSIENT_LOCAL"
        assert sum(1 for _ in reader.iter_messages(topics=["/odom"])) > 0


def test_play_republishes_the_same_topics_and_counts_at_the_rate(recording, ros_context):
    with BagReader(recording.path) as reader:
        expected = {topic: reader.topics[topic].count for topic in PLAYED}
        # The recorder discovers /clock while it records, so the bag's /clock may start later than
        # its other topics: the replay is compared with the clock span the bag really holds.
        recorded_clock = [msg.clock.sec * 10**9 + msg.clock.nanosec for _, msg in reader.decoded(["/clock"])]
    replay = play_and_count(ros_context, recording.path, list(expected), expected, ["--rate", "2"],
                            timeout=PROCESS_TIMEOUT)
    assert replay.returncode == 0, replay.output
    assert replay.counts == expected
    clock = np.array(replay.counter.clock_ns)
    recorded_span = recorded_clock[-1] - recorded_clock[0]
    assert recorded_span > 1e9, f"the recording holds only {recorded_span / 1e9:.2f} s of /clock"
    assert np.all(np.diff(clock) >= 0)  # the replayed /clock never goes back
    assert abs((clock[-1] - clock[0]) - recorded_span) <= 2e7  # and spans what was recorded (±2 ticks)
    # The pace of --rate 2 is checked on a fake clock (tests/unit/navsuite_tools/test_bag_player_pacing.py):
    # measured here from arrival times it depends on the machine's load both ways (CI runs measured
    # x1.23 and x3.31, a delayed message arriving in a burst with later ones).


def test_play_with_clock_publishes_the_bag_time(recording, ros_context):
    with BagReader(recording.path) as reader:
        start_ns, end_ns, odom_count = reader.start_ns, reader.end_ns, reader.topics["/odom"].count
    node = Node("bag_clock_listener", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    player = None
    try:
        counter = TopicCounter(node)
        counter.watch("/clock", Clock)
        counter.watch("/odom", Odometry)
        player = start_python(BAG_CLI, ["play", str(recording.path), "--topics", "/odom", "--clock", "50",
                                        "--rate", "2", "--wait-for-subscribers", "20"])
        spin_until(executor, lambda: player.poll() is not None and counter.clock_ns
                   and counter.clock_ns[-1] == end_ns, PROCESS_TIMEOUT, "the played /clock to reach the end")
        output = stop_process(player)
        assert player.returncode == 0, output
        clock = np.array(counter.clock_ns)
        assert clock[0] == start_ns and np.all(np.diff(clock) >= 0)
        assert len(clock) >= 5  # published at 50 Hz for the ~1.5 s of playback, not only at the ends
        assert abs(counter.counts["/odom"] - odom_count) <= 1
    finally:
        if player is not None:
            stop_process(player)
        executor.shutdown()
        node.destroy_node()


def test_looping_play_offers_latched_topics_transient_local_and_stops_on_sigint(recording, ros_context):
    node = Node("bag_qos_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    player = start_python(BAG_CLI, ["play", str(recording.path), "--loop", "--rate", "4",
                                    "--topics", "/tf_static", "/odom"])
    try:
        def offered(topic: str) -> list:
            return [info.qos_profile for info in node.get_publishers_info_by_topic(topic)
                    if info.node_name.startswith("bag_player_")]

        spin_until(executor, lambda: offered("/tf_static") and offered("/odom"), PROCESS_TIMEOUT,
                   "the player's publishers to appear")
        assert offered("/tf_static")[0].durability == DurabilityPolicy.TRANSIENT_LOCAL
        assert offered("/odom")[0].durability == DurabilityPolicy.VOLATILE
        assert player.poll() is None  # --loop keeps playing
    finally:
        output = stop_process(player)
        executor.shutdown()
        node.destroy_node()
    assert player.returncode == 0, output


def test_play_unknown_topic_is_a_one_line_error(recording):
    code, output = _run("play", str(recording.path), "--topics", "/nope")
    assert code == 1
    lines = output.strip().splitlines()
    assert len(lines) == 1 and "unknown topic /nope" in lines[0], output


def test_record_unknown_topic_is_a_one_line_error(tmp_path):
    code, output = _run("record", "/no_such_topic", "-o", str(tmp_path / "x.mcap"), "--topic-timeout", "1")
    assert code == 1
    lines = output.strip().splitlines()
    assert len(lines) == 1 and "unknown topic: /no_such_topic (no publisher)" in lines[0], output


def test_record_stops_on_sigint_with_a_closed_file_and_no_traceback(tmp_path, ros_context):
    """Ctrl-C (or a supervisor's SIGINT) is the ordinary way to end ``record``: exit 0, a summary line,
    a readable file, and no exception printed, wherever the signal lands (often in topic discovery)."""
    out = tmp_path / "stopped.mcap"
    recorder = start_python(BAG_CLI, ["record", "-a", "-o", str(out)])
    probe = Node("record_probe", context=ros_context)
    try:
        expected = f"bag_recorder_{recorder.pid}"
        wait_until(lambda: expected in probe.get_node_names() or recorder.poll() is not None,
                   PROCESS_TIMEOUT, "the recorder's node on the graph")
        output = stop_process(recorder, timeout=PROCESS_TIMEOUT)
    finally:
        probe.destroy_node()
        stop_process(recorder)
    assert recorder.returncode == 0, output
    assert "Traceback" not in output and "Exception" not in output, output
    assert "recorded" in output.splitlines()[-1], output
    with BagReader(out) as reader:
        assert not reader.truncated  # closed with its summary


def test_report_from_the_recording_shows_the_driven_trajectory(recording, tmp_path):
    params = ReportParams(width_px=1000, height_px=600, dpi=80)
    out = write_report(recording.path, tmp_path / "report.png", params)
    rgb = load_rgb(out)
    assert rgb.shape[:2] == (600, 1000)
    assert pixels_near(rgb, TRUTH_COLOR) > 200
    assert distinct_colors(rgb) > 50
    with BagReader(recording.path) as reader:
        xy = np.array([(m.pose.pose.position.x, m.pose.pose.position.y)
                       for _, m in reader.decoded(["/ground_truth"])])
    assert np.hypot(*(xy[-1] - xy[0])) > 0.1  # the robot did move while recording
