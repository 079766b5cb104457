"""The measured criteria of a run, from its MCAP recording: collisions, localization error, clearance.

Why from the recording rather than a live probe: the recording is an artifact the user keeps anyway,
and its numbers are the ones the run report draws (navsuite_tools.report reads the same file), so the
verdict and the picture can never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from navsuite_tools.bag.reader import BagReader
from navsuite_tools.report.analysis import localization_error
from navsuite_tools.report.extract import load_run

#: sim2d's ground-truth clearance (std_msgs/Float64, m), found by type and name suffix as the report
#: finds its topics, so a namespaced run works too
CLEARANCE_TYPE, CLEARANCE_SUFFIX = "std_msgs/msg/Float64", "/clearance"


@dataclass(frozen=True)
class RunMetrics:
    """collisions: contacts sim2d reported; max_localization_error: m, None without both poses;
    sim_span: s of sim time between the first and last ground-truth pose (None without them);
    min_clearance: m, the smallest ground-truth clearance sim2d published (None when not recorded)."""

    collisions: int
    max_localization_error: float | None
    sim_span: float | None
    min_clearance: float | None = None


def min_clearance(mcap: Path) -> float | None:
    """The smallest value on sim2d's clearance topic in ``mcap`` (m), None when it was not recorded."""
    with BagReader(mcap) as reader:
        topics = [name for name, info in reader.topics.items()
                  if info.type == CLEARANCE_TYPE and name.endswith(CLEARANCE_SUFFIX)]
        values = [float(msg.data) for _item, msg in reader.decoded(topics)]
    return min(values) if values else None


def measure(mcap: Path) -> RunMetrics:
    """Read ``mcap`` (raises OSError or ValueError when it is missing or unreadable)."""
    run = load_run(mcap)
    error = None
    if run.truth is not None and run.amcl is not None:
        _, errors = localization_error(run.truth, run.amcl)
        error = float(errors.max()) if errors.size else None
    span = None
    if run.truth is not None and len(run.truth) >= 2:
        span = float(run.truth.t[-1] - run.truth.t[0])
    return RunMetrics(int(run.collisions.shape[0]), error, span, min_clearance(mcap))
