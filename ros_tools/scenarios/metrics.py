"""The measured criteria of a run, from its MCAP recording: collisions and localization error.

Why from the recording rather than a live probe: the recording is an artifact the user keeps anyway,
and its numbers are the ones the run report draws (ros_tools.report reads the same file), so the
verdict and the picture can never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ros_tools.report.analysis import localization_error
from ros_tools.report.extract import load_run


@dataclass(frozen=True)
class RunMetrics:
    """collisions: contacts sim2d reported; max_localization_error: m, None without both poses;
    sim_span: s of sim time between the first and last ground-truth pose (None without them)."""

    collisions: int
    max_localization_error: float | None
    sim_span: float | None


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
    return RunMetrics(int(run.collisions.shape[0]), error, span)
