"""Save and load a SLAM session's pose graph, in the role of slam_toolbox's serialize / deserialize.

Why: a map saved as pgm + yaml cannot be continued; the pose graph can. slam_toolbox writes
``<filename>.posegraph`` and ``<filename>.data``; we write the same two names with our own,
documented and versioned content (``FORMAT``, ``VERSION``):

``<filename>.posegraph`` (YAML, human-readable; written last, so it is the commit of a save)::

    format: navsuite-slam-posegraph   version: 1
    data: <filename>.data             data_sha256: <hex digest of the .data file>
    nodes: N   edges: E   loop_closures: K
    map_to_odom: [x, y, yaw]          # m, m, rad: the correction when the session was saved
    params: {<every SlamParams field>} # the parameters the graph was built with, for reference

``<filename>.data`` (numpy .npz, arrays by name; m, rad, s)::

    poses (N, 3)            node poses in the map frame
    odom (N, 3)             odometry pose at each node (the saving session's odom frame)
    laser_poses (N, 3)      sensor pose in the base frame of each node's scan
    scan_ranges (R,)        every node's ranges, concatenated; scan_offsets (N + 1,) int index them
    scan_meta (N, 4)        angle_min, angle_increment, range_min, range_max of each scan
    edge_nodes (E, 2) int   i, j of each constraint "j seen from i is at z"
    edge_z (E, 3)           z = (x, y, yaw); edge_information (E, 3, 3); edge_robust (E,) bool
    grid_cell0 (2,) int     map-frame cell index of the log-odds grid's element [0, 0]
    grid_log_odds (H, W) float32 and grid_seen (H, W) bool: the map, restored bit for bit

Both files are written to a temporary name and renamed, so a crash mid-save never leaves a
half-written graph under the requested name. Loading checks every field and raises
GraphFileError naming the file and the field; the caller (the node) keeps running.
"""

from __future__ import annotations

import hashlib
import io
import os
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import yaml

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.pose_graph import Edge

FORMAT = "navsuite-slam-posegraph"
VERSION = 1
GRAPH_SUFFIX = ".posegraph"
DATA_SUFFIX = ".data"


class GraphFileError(ValueError):
    """A serialized pose graph that cannot be read: the message names the file and the field."""


@dataclass(frozen=True)
class SlamGraph:
    """Everything needed to continue a session: see the module docstring for fields and units."""

    params: SlamParams
    poses: FloatArray
    odom: FloatArray
    scans: tuple[LaserScan, ...]
    laser_poses: FloatArray
    edges: tuple[Edge, ...]
    grid_cell0: tuple[int, int]
    grid_log_odds: npt.NDArray[np.float32]
    grid_seen: npt.NDArray[np.bool_]
    map_to_odom: Pose2D
    loop_closures: int = 0


def graph_paths(filename: str | Path) -> tuple[Path, Path]:
    """(``<filename>.posegraph``, ``<filename>.data``), as slam_toolbox names them; a ``filename``
    that already ends in ``.posegraph`` names the same pair."""
    base = Path(filename).expanduser()
    if base.suffix == GRAPH_SUFFIX:
        base = base.with_suffix("")
    return base.with_name(base.name + GRAPH_SUFFIX), base.with_name(base.name + DATA_SUFFIX)


def _atomic_write(path: Path, payload: bytes) -> None:
    temporary = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        temporary.write_bytes(payload)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def write_graph(graph: SlamGraph, filename: str | Path) -> tuple[Path, Path]:
    """Write ``graph`` to ``<filename>.posegraph`` and ``<filename>.data``; return both paths.

    Raises OSError when a file cannot be written (the folder must exist).
    """
    graph_path, data_path = graph_paths(filename)
    scans = graph.scans
    offsets = np.cumsum([0] + [len(s.ranges) for s in scans], dtype=np.int64)
    buffer = io.BytesIO()
    np.savez(
        buffer,
        poses=np.asarray(graph.poses, dtype=np.float64).reshape(-1, 3),
        odom=np.asarray(graph.odom, dtype=np.float64).reshape(-1, 3),
        laser_poses=np.asarray(graph.laser_poses, dtype=np.float64).reshape(-1, 3),
        scan_ranges=np.concatenate([s.ranges for s in scans]) if scans else np.zeros(0),
        scan_offsets=offsets,
        scan_meta=np.array([(s.angle_min, s.angle_increment, s.range_min, s.range_max) for s in scans],
                           dtype=np.float64).reshape(-1, 4),
        edge_nodes=np.array([(e.i, e.j) for e in graph.edges], dtype=np.int64).reshape(-1, 2),
        edge_z=np.array([e.z for e in graph.edges], dtype=np.float64).reshape(-1, 3),
        edge_information=np.array([e.information for e in graph.edges], dtype=np.float64).reshape(-1, 3, 3),
        edge_robust=np.array([e.robust for e in graph.edges], dtype=bool),
        grid_cell0=np.array(graph.grid_cell0, dtype=np.int64),
        grid_log_odds=np.asarray(graph.grid_log_odds, dtype=np.float32),
        grid_seen=np.asarray(graph.grid_seen, dtype=bool),
    )
    data = buffer.getvalue()
    header = {
        "format": FORMAT,
        "version": VERSION,
        "data": data_path.name,
        "data_sha256": hashlib.sha256(data).hexdigest(),
        "nodes": len(graph.poses),
        "edges": len(graph.edges),
        "loop_closures": int(graph.loop_closures),
        "map_to_odom": [float(v) for v in graph.map_to_odom],
        "params": {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(graph.params).items()},
    }
    _atomic_write(data_path, data)
    _atomic_write(graph_path, yaml.safe_dump(header, sort_keys=False).encode())
    return graph_path, data_path


def _array(arrays: Any, path: Path, name: str, shape: tuple[int | None, ...], kind: str) -> Any:
    """``arrays[name]`` checked for presence, dtype kind ('f', 'i', 'b') and shape (None: any)."""
    if name not in arrays.files:
        raise GraphFileError(f"{path}: field '{name}' is missing")
    value = arrays[name]
    if value.dtype.kind != kind or value.ndim != len(shape) or any(
        want is not None and have != want for have, want in zip(value.shape, shape, strict=True)
    ):
        raise GraphFileError(f"{path}: field '{name}' has dtype {value.dtype} and shape {value.shape}, "
                             f"expected kind '{kind}' and shape {shape}")
    if kind == "f" and name != "scan_ranges" and not np.isfinite(value).all():
        raise GraphFileError(f"{path}: field '{name}' holds a value that is not finite")
    return value


def _read_header(graph_path: Path) -> dict[str, Any]:
    try:
        header = yaml.safe_load(graph_path.read_text())
    except OSError as error:
        raise GraphFileError(f"{graph_path}: cannot read the pose graph: {error.strerror}") from error
    except yaml.YAMLError as error:
        raise GraphFileError(f"{graph_path}: not YAML: {error}") from error
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise GraphFileError(f"{graph_path}: field 'format' must be '{FORMAT}'")
    if header.get("version") != VERSION:
        raise GraphFileError(f"{graph_path}: field 'version' is {header.get('version')!r}; "
                             f"this build reads version {VERSION}")
    for key in ("nodes", "edges", "loop_closures"):
        if not isinstance(header.get(key), int) or header[key] < 0:
            raise GraphFileError(f"{graph_path}: field '{key}' must be a count, got {header.get(key)!r}")
    m2o = header.get("map_to_odom")
    if not (isinstance(m2o, list) and len(m2o) == 3 and all(isinstance(v, int | float) for v in m2o)):
        raise GraphFileError(f"{graph_path}: field 'map_to_odom' must be [x, y, yaw], got {m2o!r}")
    return header


def _params(graph_path: Path, raw: object) -> SlamParams:
    if not isinstance(raw, dict):
        raise GraphFileError(f"{graph_path}: field 'params' must be a mapping")
    known = SlamParams.__dataclass_fields__
    values: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in raw.items() if k in known}
    try:
        return SlamParams(**values)
    except (TypeError, ValueError) as error:
        raise GraphFileError(f"{graph_path}: field 'params': {error}") from error


def read_graph(filename: str | Path) -> SlamGraph:
    """Read ``<filename>.posegraph`` and its ``.data``; raise GraphFileError naming file and field."""
    graph_path, data_path = graph_paths(filename)
    header = _read_header(graph_path)
    params = _params(graph_path, header.get("params"))
    try:
        data = data_path.read_bytes()
    except OSError as error:
        raise GraphFileError(f"{data_path}: cannot read the scan data: {error.strerror}") from error
    if hashlib.sha256(data).hexdigest() != header.get("data_sha256"):
        raise GraphFileError(f"{graph_path}: field 'data_sha256' does not match {data_path} "
                             "(the two files are from different saves, or the data is damaged)")
    try:
        arrays = np.load(io.BytesIO(data), allow_pickle=False)
    except (OSError, ValueError) as error:
        raise GraphFileError(f"{data_path}: not a numpy .npz archive: {error}") from error
    n, e = header["nodes"], header["edges"]

    def get(name: str, shape: tuple[int | None, ...], kind: str = "f") -> Any:
        return _array(arrays, data_path, name, shape, kind)

    poses, odom, lasers = get("poses", (n, 3)), get("odom", (n, 3)), get("laser_poses", (n, 3))
    offsets, meta = get("scan_offsets", (n + 1,), "i"), get("scan_meta", (n, 4))
    ranges = get("scan_ranges", (None,))
    if offsets[0] != 0 or offsets[-1] != len(ranges) or np.any(np.diff(offsets) < 0):
        raise GraphFileError(f"{data_path}: field 'scan_offsets' does not index 'scan_ranges'")
    try:
        scans = tuple(
            LaserScan(ranges[offsets[k] : offsets[k + 1]].copy(), *map(float, meta[k])) for k in range(n)
        )
    except ValueError as error:
        raise GraphFileError(f"{data_path}: field 'scan_meta': {error}") from error
    nodes, z = get("edge_nodes", (e, 2), "i"), get("edge_z", (e, 3))
    information, robust = get("edge_information", (e, 3, 3)), get("edge_robust", (e,), "b")
    if e and (nodes.min() < 0 or nodes.max() >= n):
        raise GraphFileError(f"{data_path}: field 'edge_nodes' names a node outside 0..{n - 1}")
    edges = tuple(
        Edge(int(i), int(j), (float(z[k, 0]), float(z[k, 1]), float(z[k, 2])), information[k].copy(),
             bool(robust[k]))
        for k, (i, j) in enumerate(nodes)
    )
    log_odds, seen = get("grid_log_odds", (None, None)), get("grid_seen", (None, None), "b")
    if log_odds.shape != seen.shape:
        raise GraphFileError(
            f"{data_path}: field 'grid_seen' has shape {seen.shape}, 'grid_log_odds' {log_odds.shape}"
        )
    cell0 = get("grid_cell0", (2,), "i")
    return SlamGraph(params, poses, odom, scans, lasers, edges, (int(cell0[0]), int(cell0[1])),
                     log_odds.astype(np.float32), seen, Pose2D(*map(float, header["map_to_odom"])),
                     header["loop_closures"])
