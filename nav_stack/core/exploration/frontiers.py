"""Frontier cells (known free next to unknown) and their 8-connected clusters.

Why 4-neighbours for detection and 8-neighbours for clustering: a free cell touching unknown only
diagonally has a known cell on both sides of that corner, so it does not border the unknown;
but a frontier running diagonally is one frontier, not a chain of single cells. Cells outside
the grid count as unknown: a SLAM map cropped to what was seen still has frontiers at its edge.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.grid import FloatArray, GridSpec, IntArray

Occupancy = npt.NDArray[np.int8]
BoolArray = npt.NDArray[np.bool_]


def free_mask(occupancy: Occupancy, occupied_threshold: int) -> BoolArray:
    """Known cells below the occupied threshold."""
    return np.asarray((occupancy >= 0) & (occupancy < occupied_threshold), dtype=np.bool_)


def frontier_mask(occupancy: Occupancy, occupied_threshold: int) -> BoolArray:
    """Free cells with an unknown (or off-grid) 4-neighbour."""
    unknown = np.pad(occupancy < 0, 1, constant_values=True)
    touches = unknown[:-2, 1:-1] | unknown[2:, 1:-1] | unknown[1:-1, :-2] | unknown[1:-1, 2:]
    return free_mask(occupancy, occupied_threshold) & touches


def label_clusters(mask: BoolArray) -> list[IntArray]:
    """8-connected components of ``mask`` as arrays of flat indices (row-major), largest first."""
    height, width = mask.shape
    remaining = set(np.flatnonzero(mask).tolist())
    clusters: list[IntArray] = []
    while remaining:
        seed = remaining.pop()
        members = [seed]
        queue = deque([seed])
        while queue:
            row, col = divmod(queue.popleft(), width)
            for dr in (-1, 0, 1):
                r = row + dr
                if r < 0 or r >= height:
                    continue
                for dc in (-1, 0, 1):
                    c = col + dc
                    if 0 <= c < width and (n := r * width + c) in remaining:
                        remaining.remove(n)
                        members.append(n)
                        queue.append(n)
        clusters.append(np.array(sorted(members), dtype=np.int64))
    clusters.sort(key=len, reverse=True)
    return clusters


@dataclass(frozen=True)
class Frontier:
    """One frontier cluster.

    Attributes:
        cells: (K, 2) cell indices ``(mx, my)``.
        size: length (m) as explore_lite measures it: number of cells × resolution.
        middle: centre (m) of the cluster cell nearest the mean of the cell centres (on the frontier even
            when it bends).
    """

    cells: IntArray
    size: float
    middle: tuple[float, float]


def find_frontiers(
    occupancy: Occupancy, spec: GridSpec, occupied_threshold: int, min_size: float = 0.0
) -> list[Frontier]:
    """Frontier clusters of at least ``min_size`` metres, largest first."""
    if occupancy.shape != spec.shape:
        raise ValueError(f"occupancy shape {occupancy.shape} does not match the grid spec {spec.shape}")
    out: list[Frontier] = []
    for flat in label_clusters(frontier_mask(occupancy, occupied_threshold)):
        size = len(flat) * spec.resolution
        if size < min_size:
            continue
        my, mx = np.divmod(flat, spec.width)
        xs, ys = spec.cell_to_world(mx, my)
        cx, cy = float(xs.mean()), float(ys.mean())
        k = int(np.argmin((xs - cx) ** 2 + (ys - cy) ** 2))
        out.append(Frontier(np.column_stack((mx, my)), size, (float(xs[k]), float(ys[k]))))
    return out


def unknown_area(occupancy: Occupancy, spec: GridSpec, points: FloatArray, half_side: float) -> FloatArray:
    """Unknown area (m²) in the square of half side ``half_side`` (m) around each (N, 2) point.

    Counted with a summed-area table, so the cost does not depend on the square's size.
    """
    table = np.zeros((spec.height + 1, spec.width + 1), dtype=np.int64)
    table[1:, 1:] = np.cumsum(np.cumsum(occupancy < 0, axis=0), axis=1)
    mx, my = spec.world_to_cell(points[:, 0], points[:, 1])
    reach = round(half_side / spec.resolution)
    c0, c1 = np.clip(mx - reach, 0, spec.width), np.clip(mx + reach + 1, 0, spec.width)
    r0, r1 = np.clip(my - reach, 0, spec.height), np.clip(my + reach + 1, 0, spec.height)
    counts = table[r1, c1] - table[r0, c1] - table[r1, c0] + table[r0, c0]
    return np.asarray(counts * spec.resolution**2, dtype=np.float64)
