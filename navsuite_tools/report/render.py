"""Drawing a run report PNG with matplotlib's Agg backend (no display, no pyplot global state).

Layout: the map panel on the left (occupancy grid, ground truth, AMCL, plans, goals,
collisions); on the right the localization error over time above the state-machine timeline.
Both time axes are seconds since the run's first stamp.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from navsuite_tools.report.analysis import distinct_points, localization_error, state_segments
from navsuite_tools.report.extract import GridMap, RunData, load_run

TRUTH_COLOR = "#2ca02c"
AMCL_COLOR = "#1f77b4"
PLAN_COLOR = "#ff7f0e"
GOAL_COLOR = "#d62728"
COLLISION_COLOR = "#e41a1c"
UNKNOWN_RGB = (0.80, 0.84, 0.88)
#: State bar colours (ColorBrewer Set3): pastel, so they never look like a trajectory colour.
STATE_COLORS = ("#8dd3c7", "#bebada", "#fdb462", "#80b1d3", "#fccde5", "#ffed6f", "#bc80bd", "#d9d9d9",
                "#fb8072", "#b3de69")
#: Smallest side (m) of the map panel's view when no map was recorded.
MIN_VIEW = 2.0
#: Plan ends closer than this (m) are drawn as one goal: replanning repeats the same end.
GOAL_TOLERANCE = 0.05


@dataclass(frozen=True)
class ReportParams:
    """Report appearance.

    Attributes:
        width_px, height_px: image size in pixels.
        dpi: dots per inch (fonts scale with it).
        map_choice: ``last`` or ``first`` recorded map as background (SLAM maps grow).
        all_plans: draw every global plan faintly under the latest one.
    """

    width_px: int = 1600
    height_px: int = 900
    dpi: int = 100
    map_choice: str = "last"
    all_plans: bool = True

    def __post_init__(self) -> None:
        if self.width_px < 200 or self.height_px < 150 or self.dpi < 20:
            raise ValueError(
                f"report size {self.width_px}x{self.height_px} px at {self.dpi} dpi is too small"
            )
        if self.map_choice not in ("first", "last"):
            raise ValueError(f"map_choice must be 'first' or 'last', got '{self.map_choice}'")


def map_rgb(grid: GridMap) -> np.ndarray:
    """Occupancy (0 free … 100 occupied, -1 unknown) as an RGB image: white to black, unknown tinted."""
    data = grid.data.astype(float)
    gray = 1.0 - np.clip(data, 0, 100) / 100.0
    rgb = np.repeat(gray[:, :, None], 3, axis=2)
    rgb[data < 0] = UNKNOWN_RGB
    return rgb


def _note(ax: Axes, text: str) -> None:
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, color="0.4")


def _draw_map(ax: Axes, run: RunData, params: ReportParams) -> None:
    ax.set_facecolor(UNKNOWN_RGB)
    grid = run.last_map if params.map_choice == "last" else run.first_map
    if grid is not None:
        ax.imshow(map_rgb(grid), origin="lower", extent=grid.extent, interpolation="nearest", zorder=0)
    plans = run.plans if params.all_plans else run.plans[-1:]
    for plan in plans[:-1]:
        ax.plot(plan[:, 0], plan[:, 1], color=PLAN_COLOR, lw=0.8, alpha=0.25, zorder=2)
    if run.plans:
        latest = run.plans[-1]
        ax.plot(latest[:, 0], latest[:, 1], color=PLAN_COLOR, lw=1.8, label=f"global plan ({len(run.plans)})",
                zorder=3)
        ends = distinct_points(np.array([plan[-1] for plan in run.plans]), GOAL_TOLERANCE)
        ax.scatter(ends[:, 0], ends[:, 1], marker="x", s=60, color="#9467bd", label="plan ends", zorder=6)
    if run.truth is not None:
        xy = run.truth.xy
        ax.plot(xy[:, 0], xy[:, 1], color=TRUTH_COLOR, lw=2.2, label="ground truth", zorder=4)
        ax.scatter(xy[:1, 0], xy[:1, 1], marker="o", s=70, color=TRUTH_COLOR, edgecolors="k", label="start",
                   zorder=7)
        ax.scatter(xy[-1:, 0], xy[-1:, 1], marker="s", s=60, color=TRUTH_COLOR, edgecolors="k", label="end",
                   zorder=7)
    if run.amcl is not None:
        xy = run.amcl.xy
        ax.plot(xy[:, 0], xy[:, 1], color=AMCL_COLOR, lw=1.2, ls="--", marker=".", ms=3, label="AMCL",
                zorder=5)
    if len(run.goals):
        goals = run.goals
        ax.scatter(goals[:, 0], goals[:, 1], marker="*", s=220, color=GOAL_COLOR, edgecolors="k",
                   label="/goal_pose", zorder=8)
        ax.quiver(goals[:, 0], goals[:, 1], np.cos(goals[:, 2]), np.sin(goals[:, 2]), color=GOAL_COLOR,
                  angles="xy", scale_units="inches", scale=3.0, width=0.004, zorder=8)
    if len(run.collisions):
        hits = run.collisions
        ax.scatter(hits[:, 1], hits[:, 2], marker="X", s=110, color=COLLISION_COLOR, edgecolors="k",
                   label=f"collisions ({len(hits)})", zorder=9)
    if not ax.has_data():
        _note(ax, "no map, trajectory or plan recorded")
    if grid is None:  # no map to frame the view: centre the data, at least MIN_VIEW m wide
        (x0, y0), (x1, y1) = ax.dataLim.get_points()
        if np.isfinite([x0, y0, x1, y1]).all():
            half = max(x1 - x0, y1 - y0, MIN_VIEW) / 2 + 0.2
            cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
            ax.update_datalim([(cx - half, cy - half), (cx + half, cy + half)])
            ax.autoscale_view()
        ax.grid(alpha=0.4, color="white")
    ax.set_aspect("equal", adjustable="box" if grid is not None else "datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title = "map" if grid is None else f"map ({params.map_choice} of {run.map_count})"
    ax.set_title(title)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", fontsize="small", framealpha=0.85)


def _draw_error(ax: Axes, run: RunData, t0: float) -> None:
    ax.set_title("localization error (AMCL vs ground truth)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("position error [m]")
    if run.truth is None or run.amcl is None:
        _note(ax, "needs ground_truth and /amcl_pose")
        return
    t, error = localization_error(run.truth, run.amcl)
    if not len(t):
        _note(ax, "AMCL stamps outside the ground-truth time span")
        return
    ax.plot(t - t0, error, color=AMCL_COLOR, lw=1.5, marker=".", ms=4)
    ax.axhline(float(error.mean()), color="0.5", ls=":", lw=1)
    ax.set_ylim(bottom=0)
    ax.text(0.99, 0.95, f"mean {error.mean():.3f} m   max {error.max():.3f} m   final {error[-1]:.3f} m",
            ha="right", va="top", transform=ax.transAxes, fontsize="small")
    ax.grid(alpha=0.3)


def _draw_timeline(ax: Axes, run: RunData, t0: float) -> None:
    ax.set_title("state machine" + (" (red: collisions)" if len(run.collisions) else ""))
    ax.set_xlabel("time [s]")
    end = run.truth.t[-1] if run.truth is not None and len(run.truth) else t0 + run.duration
    segments = state_segments(run.transitions, end)
    for hit in run.collisions[:, 0]:
        ax.axvline(hit - t0, color=COLLISION_COLOR, lw=1.0, alpha=0.7)
    if not segments:
        _note(ax, "no /<Sm>/smacc/transition_log recorded")
        ax.set_yticks([])
        return
    several = len({s.machine for s in segments}) > 1
    rows: dict[str, int] = {}
    for segment in segments:
        rows.setdefault(f"{segment.machine}: {segment.state}" if several else segment.state, len(rows))
    colors = [STATE_COLORS[i % len(STATE_COLORS)] for i in range(len(rows))]
    for segment in segments:
        label = f"{segment.machine}: {segment.state}" if several else segment.state
        row = rows[label]
        start, width = segment.start - t0, max(segment.end - segment.start, 1e-3)
        ax.broken_barh([(start, width)], (row - 0.35, 0.7), color=colors[row], edgecolor="0.3", lw=0.6)
        if segment.tag:
            ax.text(start, row - 0.38, segment.tag, fontsize="x-small", va="bottom", clip_on=True)
    ax.set_yticks(range(len(rows)), list(rows), fontsize="small")
    ax.set_ylim(len(rows) - 0.4, -0.8)
    ax.grid(axis="x", alpha=0.3)


def render(run: RunData, out_png: Path, params: ReportParams) -> Path:
    """Draw ``run`` into ``out_png`` (parent folders are created) and return its path."""
    figure = Figure(figsize=(params.width_px / params.dpi, params.height_px / params.dpi), dpi=params.dpi)
    FigureCanvasAgg(figure)
    grid = figure.add_gridspec(2, 2, width_ratios=(1.15, 1.0), left=0.05, right=0.98, bottom=0.07,
                               top=0.91, wspace=0.22, hspace=0.35)
    t0 = run.time_origin()
    _draw_map(figure.add_subplot(grid[:, 0]), run, params)
    _draw_error(figure.add_subplot(grid[0, 1]), run, t0)
    _draw_timeline(figure.add_subplot(grid[1, 1]), run, t0)
    figure.suptitle(f"run report: {run.source.name}   ({run.duration:.1f} s recorded)")
    out_png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(out_png, dpi=params.dpi, format="png")
    return out_png


def write_report(mcap_path: str | Path, out_png: str | Path, params: ReportParams | None = None) -> Path:
    """Read a recording and write its report PNG; returns the PNG's absolute path.

    Raises:
        BagError: the recording cannot be read.
    """
    run = load_run(mcap_path)
    return render(run, Path(out_png), params or ReportParams()).resolve()
