"""Exact Euclidean distance (in cells) to the nearest marked cell, up to a cap, in pure numpy.

Why: both the inflation layer (costs within ``inflation_radius``) and AMCL's likelihood field
(distances up to ``laser_likelihood_max_dist``) need the distance from every cell to the nearest
obstacle cell, but only up to a bounded radius R. A bounded two-pass transform is exact there and
vectorises well:

1. along each column, the distance g to the nearest marked cell in that column (two cumulative
   scans), capped at R + 1;
2. along each row, d²(x) = min over |k| ≤ R of g(x + k)² + k², i.e. 2R shifted minimums over the
   whole array. Every nearest obstacle within R lies within R columns, so results ≤ R² are exact
   (they equal the Felzenszwalb transform); larger values only mean "beyond R".

Distances are between cell centres, as Nav2's inflation kernel and amcl's map_update_cspace use.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

BoolArray = npt.NDArray[np.bool_]
SquaredDistances = npt.NDArray[np.int32]


def _column_distance(mask: BoolArray, cap: int) -> npt.NDArray[np.int32]:
    """Distance in cells along axis 0 to the nearest True cell of the same column, capped at ``cap``."""
    height = mask.shape[0]
    far = height + cap + 1
    rows = np.arange(height, dtype=np.int32)[:, None]
    above = np.where(mask, rows, np.int32(-far))
    np.maximum.accumulate(above, axis=0, out=above)
    below = np.where(mask, rows, np.int32(height + far))
    below = np.minimum.accumulate(below[::-1], axis=0)[::-1]
    dist = np.minimum(rows - above, below - rows)
    np.minimum(dist, cap, out=dist)
    return dist


def squared_distance_cells(mask: BoolArray, max_cells: int) -> SquaredDistances:
    """Squared distance in cells from every cell to the nearest True cell of ``mask``.

    Exact wherever the result is ≤ ``max_cells``²; every farther cell (and every cell when the mask
    is empty) holds ``max_cells``² + 1.
    """
    if mask.ndim != 2:
        raise ValueError(f"mask must be 2-D, got shape {mask.shape}")
    if max_cells < 0:
        raise ValueError(f"max_cells must be >= 0, got {max_cells}")
    beyond = max_cells * max_cells + 1
    if not mask.any():
        return np.full(mask.shape, beyond, dtype=np.int32)
    dtype = np.uint16 if 2 * (max_cells + 1) ** 2 < np.iinfo(np.uint16).max else np.int32
    g = _column_distance(mask, max_cells + 1).astype(dtype)
    g2 = g * g
    best = g2.copy()
    width = mask.shape[1]
    for k in range(1, min(max_cells, width - 1) + 1):
        shifted = g2[:, :-k] + dtype(k * k)
        np.minimum(best[:, k:], shifted, out=best[:, k:])
        shifted = g2[:, k:] + dtype(k * k)
        np.minimum(best[:, :-k], shifted, out=best[:, :-k])
    out: SquaredDistances = best.astype(np.int32)
    np.minimum(out, beyond, out=out)
    return out
