"""MCAP files written by BagWriter: ros2 profile layout, read-back, info text, errors, QoS text.

No DDS here: rclpy is used only for its CDR serializer and QoS classes.
"""

from __future__ import annotations

import io

import pytest
import yaml
from geometry_msgs.msg import Twist
from mcap.reader import make_reader
from mcap.writer import Writer
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import serialize_message

from navsuite_tools.bag.info import format_info
from navsuite_tools.bag.main import main
from navsuite_tools.bag.qos import offered_qos_yaml, parse_offered_qos, playback_profile, request_for_offers
from navsuite_tools.bag.reader import BagError, BagReader
from navsuite_tools.bag.recorder import RecordOptions
from navsuite_tools.bag.schema import message_definition
from navsuite_tools.bag.writer import BagWriter
from ros_tools.status_line import StatusLine, topic_counts
from tests.helpers.bag_synthetic import DURATION, T0, write_synthetic_run

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
SENSOR = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return write_synthetic_run(tmp_path_factory.mktemp("bag") / "run.mcap")


def test_file_follows_the_ros2_profile(run):
    with run.path.open("rb") as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        names = {s.name for s in summary.schemas.values()}
        assert names >= {"nav_msgs/msg/Odometry", "nav_msgs/msg/OccupancyGrid"}
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        assert all("offered_qos_profiles" in c.metadata for c in summary.channels.values())
        assert summary.chunk_indexes and {c.compression for c in summary.chunk_indexes} == {"zstd"}
        assert summary.statistics.message_count == sum(run.counts.values())


def test_reader_reports_topics_counts_and_time_range(run):
    with BagReader(run.path) as reader:
        assert {name: info.count for name, info in reader.topics.items()} == run.counts
        assert reader.topics["/ground_truth"].type == "nav_msgs/msg/Odometry"
        assert reader.start_ns == int(T0 * 1e9)
        assert reader.duration_ns == int(DURATION * 1e9)


def test_messages_come_back_decoded_in_log_time_order(run):
    with BagReader(run.path) as reader:
        items = list(reader.decoded(["/ground_truth", "/amcl_pose"]))
    times = [item.log_time for item, _ in items]
    assert times == sorted(times)
    assert len(items) == run.counts["/ground_truth"] + run.counts["/amcl_pose"]
    _, first = items[0]
    assert first.header.frame_id == "map"
    assert first.pose.pose.position.x == pytest.approx(1.2, abs=0.2)


def test_write_message_round_trip_keeps_values(tmp_path):
    path = tmp_path / "twist.mcap"
    with BagWriter(path, compression="lz4") as writer:
        for k in range(3):
            msg = Twist()
            msg.linear.x = 0.1 * k
            writer.write_message("/cmd_vel", msg, 1_000 + k)
    with BagReader(path) as reader:
        values = [msg.linear.x for _, msg in reader.decoded(["/cmd_vel"])]
    assert values == pytest.approx([0.0, 0.1, 0.2])


def test_info_text_lists_every_topic_with_type_and_count(run):
    with BagReader(run.path) as reader:
        text = format_info(reader)
    assert "Duration:          20.000000000s" in text
    assert f"Messages:          {sum(run.counts.values())}" in text
    for topic, count in run.counts.items():
        line = next(line for line in text.splitlines() if f"Topic: {topic} " in line)
        assert f"| Count: {count} |" in line
    assert "Type: smacc2_msgs/msg/SmaccTransitionLogEntry" in text


def test_info_cli_prints_summary(run, capsys):
    assert main(["info", str(run.path)]) == 0
    assert "Topic: /map" in capsys.readouterr().out


@pytest.mark.parametrize("content", [b"", b"not an mcap file at all", b"\x89MCAP0\r\n" + b"\x00" * 40])
def test_malformed_files_raise_bag_error_naming_the_file(tmp_path, content):
    path = tmp_path / "bad.mcap"
    path.write_bytes(content)
    with pytest.raises(BagError, match=r"bad\.mcap"):
        BagReader(path)


def test_truncated_recording_is_read_or_rejected_cleanly(run, tmp_path):
    data = run.path.read_bytes()
    path = tmp_path / "cut.mcap"
    path.write_bytes(data[: len(data) // 2])
    try:
        with BagReader(path) as reader:
            assert reader.truncated
            assert sum(1 for _ in reader.messages()) <= sum(run.counts.values())
    except BagError as exc:  # cut inside the first chunk: nothing complete to read
        assert "cut.mcap" in str(exc)


def test_cli_errors_are_one_line_and_exit_1(tmp_path, capsys):
    assert main(["info", str(tmp_path / "missing.mcap")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.mcap" in err[0]


def test_unknown_topic_is_reported_with_the_recorded_ones(run):
    with BagReader(run.path) as reader:
        messages = reader.messages(["/nope"])
        with pytest.raises(BagError, match=r"unknown topic /nope.*recorded: .*/map"):
            next(messages)


def test_offered_qos_text_is_rosbag2_version_9():
    text = offered_qos_yaml([LATCHED, SENSOR])
    entries = yaml.safe_load(text)
    assert entries[0]["durability"] == "transient_local" and entries[0]["reliability"] == "reliable"
    assert entries[1]["reliability"] == "best_effort" and entries[1]["history"] == "keep_last"
    assert entries[0]["deadline"] == {"sec": 0, "nsec": 0}
    assert list(entries[0]) == ["history", "depth", "reliability", "durability", "deadline", "lifespan",
                                "liveliness", "liveliness_lease_duration", "avoid_ros_namespace_conventions"]
    back = parse_offered_qos(text)
    assert [p.durability for p in back] == [DurabilityPolicy.TRANSIENT_LOCAL, DurabilityPolicy.VOLATILE]
    assert [p.reliability for p in back] == [ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT]


def test_older_integer_qos_text_and_unknown_history_are_accepted():
    text = "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n  liveliness: 1\n"
    (profile,) = parse_offered_qos(text)
    assert profile.history == HistoryPolicy.KEEP_LAST
    assert profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert profile.depth >= 1


def test_bad_qos_text_names_the_key():
    with pytest.raises(ValueError, match="/map: durability 'sticky'"):
        parse_offered_qos("- durability: sticky\n", "/map")


def test_recording_request_matches_every_publisher():
    both = request_for_offers([LATCHED, SENSOR])
    assert both.reliability == ReliabilityPolicy.BEST_EFFORT and both.durability == DurabilityPolicy.VOLATILE
    latched = request_for_offers([LATCHED, LATCHED])
    assert latched.reliability == ReliabilityPolicy.RELIABLE
    assert latched.durability == DurabilityPolicy.TRANSIENT_LOCAL


def test_playback_offers_the_recorded_qos_again():
    assert playback_profile(parse_offered_qos(offered_qos_yaml([LATCHED]))).durability == (
        DurabilityPolicy.TRANSIENT_LOCAL)
    assert playback_profile([LATCHED, SENSOR]).reliability == ReliabilityPolicy.RELIABLE
    assert playback_profile([]).durability == DurabilityPolicy.VOLATILE


def test_writer_rejects_unknown_compression_and_unadded_topics(tmp_path):
    with pytest.raises(ValueError, match="compression must be one of"):
        BagWriter(tmp_path / "x.mcap", compression="bz2")
    with BagWriter(tmp_path / "y.mcap") as writer, pytest.raises(ValueError, match="'/a' was not added"):
        writer.write("/a", b"", 0)


def test_recording_cut_off_without_summary_is_read_up_to_the_cut(tmp_path):
    """A killed recorder leaves no footer: its complete records are still readable."""
    stream = io.BytesIO()
    writer = Writer(stream, use_chunking=False)
    writer.start(profile="ros2")
    text = message_definition("geometry_msgs/Twist").encode()
    schema = writer.register_schema("geometry_msgs/msg/Twist", "ros2msg", text)
    channel = writer.register_channel("/cmd_vel", "cdr", schema, {})
    for k in range(5):
        writer.add_message(channel, log_time=10 - k, data=serialize_message(Twist()), publish_time=10 - k)
    path = tmp_path / "killed.mcap"
    path.write_bytes(stream.getvalue()[:-7])  # no footer, last record cut
    with BagReader(path) as reader:
        assert reader.truncated
        assert reader.topics["/cmd_vel"].count == 4
        assert [m.log_time for m in reader.messages()] == [7, 8, 9, 10]
        assert "Truncated:         yes" in format_info(reader)


def test_record_options_select_topics_like_ros2_bag(tmp_path):
    listed = RecordOptions(output=tmp_path / "a.mcap", topics=("scan", "/odom"))
    assert listed.topics == ("/scan", "/odom")
    assert listed.selects("/scan") and not listed.selects("/tf")
    every = RecordOptions(output=tmp_path / "a.mcap", all_topics=True, exclude_regex="^/rosout$")
    assert every.selects("/tf") and not every.selects("/rosout")
    assert not every.selects("/navigate_to_pose/_action/status")  # hidden unless asked for
    regex = RecordOptions(output=tmp_path / "a.mcap", regex="/(global|local)_costmap/.*")
    assert regex.selects("/local_costmap/costmap") and not regex.selects("/map")
    with pytest.raises(ValueError, match="nothing to record"):
        RecordOptions(output=tmp_path / "a.mcap")
    with pytest.raises(ValueError, match="invalid topic name 'bad topic'"):
        RecordOptions(output=tmp_path / "a.mcap", topics=("bad topic",))


def test_status_line_redraws_in_place_only_on_a_terminal():
    live, piped = io.StringIO(), io.StringIO()
    for stream, is_live in ((live, True), (piped, False)):
        status = StatusLine(stream, period=0.0, live=is_live)
        status.update("recording 1.0 s")
        status.update("recording 2.0 s")
        status.finish("recorded 10 messages")
    assert live.getvalue().count("\r") == 3 and "recording 2.0 s" in live.getvalue()
    assert piped.getvalue() == "recorded 10 messages\n"
    assert topic_counts({"/a": 1, "/b": 5, "/c": 5}, limit=2) == "/b 5  /c 5  …"
