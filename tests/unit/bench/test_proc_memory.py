"""Memory growth between the warm look and the end, and the process tree it is read from."""

from __future__ import annotations

import os

import pytest

from bench.proc_memory import MemoryGrowth, compare, descendants, largest_growth, rss_mib


def test_growth_is_in_percent_of_the_warm_figure() -> None:
    assert MemoryGrowth("sim2d", 200.0, 210.0).percent == pytest.approx(5.0)
    assert MemoryGrowth("sim2d", 200.0, 190.0).percent == pytest.approx(-5.0)
    assert MemoryGrowth("initial_pose", 40.0, None).percent is None


def test_compare_keeps_processes_seen_only_once() -> None:
    growths = compare({"sim2d": 100.0, "initial_pose": 40.0}, {"sim2d": 101.0, "nav2 (all nodes)": 300.0})
    assert [(g.name, g.warm, g.end) for g in growths] == [
        ("sim2d", 100.0, 101.0), ("initial_pose", 40.0, None), ("nav2 (all nodes)", None, 300.0)]


def test_largest_growth_ignores_processes_not_measured_twice() -> None:
    growths = compare({"a": 100.0, "b": 100.0, "c": 10.0}, {"a": 102.0, "b": 108.0, "d": 5.0})
    largest = largest_growth(growths)
    assert largest is not None and largest.name == "b"
    assert largest_growth(compare({"a": 1.0}, {})) is None


def test_this_process_is_its_own_tree_and_has_a_resident_set() -> None:
    assert descendants(os.getpid())[0] == os.getpid()
    rss = rss_mib(os.getpid())
    assert rss is not None and rss > 1.0
