"""Conversions between occupancy grids and static geometry.

* grid → geometry: a map_server map becomes a world. Occupied cells merge into few boxes (row runs,
  then identical runs stacked across rows) so pymunk has hundreds of shapes, not thousands; the lidar
  sees only the occupied/free boundary, merged into long segments.
* geometry → grid: rasterise a world into a trinary map_server image (used by
  scripts/generate_world_map.py), sampling each cell at its centre.
Both run as numpy operations per row or per run, never per cell.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from sim2d.core.geometry import FloatArray, StaticGeometry, points_in_convex
from sim2d.core.map_io import FREE_PIXEL, OCCUPIED_PIXEL, UNKNOWN_PIXEL, MapImage

IntArray = NDArray[np.int64]


def _runs(mask_rows: NDArray[np.bool_]) -> tuple[IntArray, IntArray, IntArray]:
    """Runs of True along axis 1: (row, start, end_exclusive) arrays."""
    padded = np.zeros((mask_rows.shape[0], mask_rows.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = mask_rows
    change = np.diff(padded, axis=1)
    rows_s, starts = np.nonzero(change == 1)
    _, ends = np.nonzero(change == -1)
    return rows_s.astype(np.int64), starts.astype(np.int64), ends.astype(np.int64)


def merge_boxes(occupied: NDArray[np.bool_]) -> IntArray:
    """Cover the True cells of ``occupied`` (H, W) with disjoint boxes (K, 4) [col0, row0, col1, row1).

    A run [start, end) in row r extends the box with the same run that ended in row r-1; otherwise
    it opens a new box. Loops run over runs (a few per row), not over cells.
    """
    rows, starts, ends = _runs(occupied)
    boxes: list[tuple[int, int, int, int]] = []
    growing: dict[tuple[int, int], int] = {}  # run -> first row of a box whose last row is last_row
    current: dict[tuple[int, int], int] = {}
    last_row = -2
    for r, s, e in zip(rows.tolist(), starts.tolist(), ends.tolist(), strict=True):
        if r != last_row:
            _flush(growing, boxes, last_row)
            growing = current if r == last_row + 1 else _flushed(current, boxes, last_row)
            current, last_row = {}, r
        current[(s, e)] = growing.pop((s, e), r)
    _flush(growing, boxes, last_row)
    _flush(current, boxes, last_row + 1)
    return np.array(boxes, dtype=np.int64).reshape(-1, 4)


def _flush(runs: dict[tuple[int, int], int], boxes: list[tuple[int, int, int, int]], row_end: int) -> None:
    """Close every box in ``runs``: it covers rows [row0, row_end)."""
    boxes.extend((s, row0, e, row_end) for (s, e), row0 in runs.items())
    runs.clear()


def _flushed(runs: dict[tuple[int, int], int], boxes: list[tuple[int, int, int, int]],
             last_row: int) -> dict[tuple[int, int], int]:
    """Close the boxes of a row that is not followed by the next one; nothing keeps growing."""
    _flush(runs, boxes, last_row + 1)
    return {}


def boundary_segments(occupied: NDArray[np.bool_], resolution: float,
                      origin: tuple[float, float]) -> FloatArray:
    """Segments (N, 4) (m) on the edges between occupied and other cells, merged into runs.

    Each segment is oriented with the occupied side on its left (as a CCW polygon's edges), which
    lets the lidar cull segments that face away from it.
    """
    h, w = occupied.shape
    padded = np.zeros((h + 2, w + 2), dtype=bool)
    padded[1:-1, 1:-1] = occupied
    below, above = padded[:-1, 1:-1], padded[1:, 1:-1]       # (h+1, w): grid line y = row index
    left, right = padded[1:-1, :-1], padded[1:-1, 1:]        # (h, w+1): grid line x = col index
    ox, oy = origin
    parts = []
    for mask, forward in ((above & ~below, True), (below & ~above, False)):
        r, s, e = _runs(mask)
        y = oy + r * resolution
        x0, x1 = ox + s * resolution, ox + e * resolution
        parts.append(np.column_stack((x0, y, x1, y) if forward else (x1, y, x0, y)))
    for mask, upward in ((left & ~right, True), (right & ~left, False)):
        c, s, e = _runs(mask.T.copy())
        x = ox + c * resolution
        y0, y1 = oy + s * resolution, oy + e * resolution
        parts.append(np.column_stack((x, y0, x, y1) if upward else (x, y1, x, y0)))
    return np.concatenate(parts).astype(np.float64)


def map_to_geometry(grid: MapImage) -> StaticGeometry:
    """Static geometry of a map_server map: merged boxes for collisions, boundary segments for rays."""
    cells = merge_boxes(grid.occupied)
    res, (ox, oy) = grid.resolution, grid.origin
    boxes = np.column_stack((ox + cells[:, 0] * res, oy + cells[:, 1] * res,
                             ox + cells[:, 2] * res, oy + cells[:, 3] * res)).astype(np.float64)
    return StaticGeometry(boxes=boxes, segments=boundary_segments(grid.occupied, res, grid.origin))


def rasterize(geometry: StaticGeometry, free_region: FloatArray | None, resolution: float,
              margin: float) -> tuple[NDArray[np.uint8], tuple[float, float]]:
    """Trinary image (H, W) in image row order and its origin (m) for a world.

    Obstacles → 0; inside ``free_region`` (convex CCW polygon) and not an obstacle → 254; else 205.
    The grid covers the obstacles' bounding box plus ``margin`` (m), aligned to whole cells.
    """
    xmin, ymin, xmax, ymax = geometry.bounds()
    ox = math.floor((xmin - margin) / resolution) * resolution
    oy = math.floor((ymin - margin) / resolution) * resolution
    width = math.ceil((xmax + margin - ox) / resolution)
    height = math.ceil((ymax + margin - oy) / resolution)
    xs = ox + (np.arange(width) + 0.5) * resolution
    ys = oy + (np.arange(height) + 0.5) * resolution
    gx, gy = np.meshgrid(xs, ys)
    points = np.column_stack((gx.ravel(), gy.ravel()))
    image = np.full(len(points), UNKNOWN_PIXEL, dtype=np.uint8)
    if free_region is not None:
        image[points_in_convex(points, free_region)] = FREE_PIXEL
    image[geometry.contains(points)] = OCCUPIED_PIXEL
    return image.reshape(height, width)[::-1].copy(), (round(ox, 9), round(oy, 9))
