"""A 2D pose graph and its Gauss-Newton optimisation on SE(2) (Grisetti et al., "A tutorial on
graph-based SLAM", 2010), in numpy; the chain's block-tridiagonal solve is compiled (pose_graph_jit).

Why dense: the mapper holds a few hundred nodes (one per 0.2 m travelled), so the 3n × 3n normal
equations fit comfortably in memory and one LAPACK solve is faster than assembling a sparse
matrix in Python. The first node is anchored (it defines the map frame), the rest move.

An edge (i, j, z, Ω) says "node j seen from node i is at z = (x, y, yaw)" with information Ω
(3 × 3). Its error is e = t2v(Z⁻¹ · Xi⁻¹ · Xj); each iteration linearises all edges at once.

Robust edges (loop closures) go through a Cauchy kernel by iteratively reweighted least squares:
an edge whose Mahalanobis error s = eᵀΩe is large against the rest of the graph gets its
information scaled by 1 / (1 + s / c²), so one false closure that contradicts the odometry chain
and the other closures is pulled on weakly instead of bending the whole map (Agarwal et al. 2013
make the same argument for dynamic covariance scaling). Sequential edges stay quadratic: they are
the backbone the outliers are judged against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import FloatArray, normalize_angles
from nav_stack.core.slam.pose_graph_jit import block_tridiagonal_solve


@dataclass(frozen=True)
class Edge:
    """Constraint: node ``j`` seen from node ``i`` is at ``z`` = (x, y, yaw), with 3 × 3 ``information``.

    ``robust`` edges (loop closures) are down-weighted by the Cauchy kernel when they disagree
    with the rest of the graph.
    """

    i: int
    j: int
    z: tuple[float, float, float]
    information: FloatArray
    robust: bool = False


def robust_weights(
    errors: FloatArray, info: FloatArray, robust: npt.NDArray[np.bool_], width: float
) -> FloatArray:
    """IRLS weights (E,) of the Cauchy kernel of ``width`` (Mahalanobis units); 1 for non-robust edges."""
    s = np.einsum("ei,eij,ej->e", errors, info, errors)
    return np.where(robust, 1.0 / (1.0 + s / (width * width)), 1.0)


def relative_pose(a: FloatArray, b: FloatArray) -> FloatArray:
    """Poses ``b`` (N, 3) expressed in the frames of poses ``a`` (N, 3)."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy, normalize_angles(b[:, 2] - a[:, 2])))


def edge_errors(poses: FloatArray, edges: list[Edge]) -> FloatArray:
    """(E, 3) errors of all edges at ``poses`` (N, 3)."""
    i = np.array([e.i for e in edges])
    j = np.array([e.j for e in edges])
    z = np.array([e.z for e in edges], dtype=np.float64)
    return relative_pose(z, relative_pose(poses[i], poses[j]))


def total_error(poses: FloatArray, edges: list[Edge]) -> float:
    """Sum of squared Mahalanobis edge errors (χ²)."""
    if not edges:
        return 0.0
    e = edge_errors(poses, edges)
    info = np.stack([edge.information for edge in edges])
    return float(np.einsum("ei,eij,ej->", e, info, e))


def _scatter(index: npt.NDArray[np.int64], values: FloatArray, n: int) -> FloatArray:
    """Sum (E, 3) ``values`` into (n, 3) rows ``index`` (bincount per column: faster than np.add.at)."""
    return np.column_stack([np.bincount(index, values[:, k], minlength=n) for k in range(3)])


def _linearize(
    x: FloatArray, i: npt.NDArray[np.int64], j: npt.NDArray[np.int64], z: FloatArray, rz_t: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Errors (E, 3) and Jacobians A = ∂e/∂xi, B = ∂e/∂xj (E, 3, 3) of every edge at ``x``."""
    err = relative_pose(z, relative_pose(x[i], x[j]))
    ci, si = np.cos(x[i, 2]), np.sin(x[i, 2])
    ri_t = np.stack((np.column_stack((ci, si)), np.column_stack((-si, ci))), axis=1)
    dri_t = np.stack((np.column_stack((-si, ci)), np.column_stack((-ci, -si))), axis=1)  # d(Riᵀ)/dθi
    dt = (x[j, :2] - x[i, :2])[:, :, None]
    a = np.zeros((len(i), 3, 3))
    b = np.zeros((len(i), 3, 3))
    rzri = rz_t @ ri_t
    a[:, :2, :2] = -rzri
    a[:, :2, 2] = (rz_t @ dri_t @ dt)[:, :, 0]
    a[:, 2, 2] = -1.0
    b[:, :2, :2] = rzri
    b[:, 2, 2] = 1.0
    return err, a, b


def _solve_normal_equations(
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    a: FloatArray,
    b: FloatArray,
    info: FloatArray,
    rhs: FloatArray,
) -> FloatArray:
    """Solve H·dx = rhs (H = Σ Jᵀ Ω J over the edges, node 0 fixed) without forming H.

    Why this way: the mapper's graph is a chain (edge k−1 → k for every node) plus a few loop
    edges. The chain alone gives a block-tridiagonal T, solved in O(n); each loop edge adds a rank-3
    term U·Uᵀ, folded in with the Woodbury identity H⁻¹ = T⁻¹ − T⁻¹U (I + UᵀT⁻¹U)⁻¹ UᵀT⁻¹. A few
    hundred nodes then solve in milliseconds where a dense 3n × 3n solve takes a large fraction
    of a second. Graphs without a complete chain fall back to the dense solve.
    """
    n = len(rhs)
    chain = np.flatnonzero(j == i + 1)
    first = np.full(n, -1, dtype=np.int64)
    first[j[chain][::-1]] = chain[::-1]  # the first chain edge ending at each node
    if np.any(first[1:] < 0):
        return _dense_solve(i, j, a, b, info, rhs)
    is_chain = np.zeros(len(i), dtype=bool)
    is_chain[first[1:]] = True
    at_o = np.transpose(a, (0, 2, 1)) @ info
    bt_o = np.transpose(b, (0, 2, 1)) @ info
    diag = np.zeros((n, 3, 3))
    c = first[1:]
    np.add.at(diag, i[c], at_o[c] @ a[c])
    np.add.at(diag, j[c], bt_o[c] @ b[c])
    upper = at_o[c] @ b[c]  # block (k-1, k)
    loops = np.flatnonzero(~is_chain)
    columns = np.zeros((n, 3, 3 * len(loops)))
    for col, e in enumerate(loops):
        root = np.linalg.cholesky(info[e])
        columns[i[e], :, 3 * col : 3 * col + 3] += a[e].T @ root
        columns[j[e], :, 3 * col : 3 * col + 3] += b[e].T @ root
    both = np.concatenate((rhs[:, :, None], columns), axis=2)[1:]  # drop the fixed node 0
    solved = block_tridiagonal_solve(diag[1:], np.ascontiguousarray(upper[1:]), np.ascontiguousarray(both))
    t_rhs, t_u = solved[:, :, 0].reshape(-1), solved[:, :, 1:].reshape(3 * (n - 1), -1)
    if loops.size:
        # U is zero outside the rows of the loop edges' end nodes: Uᵀ·X only needs those rows
        ends = np.unique(np.concatenate((i[loops], j[loops])))
        rows = (3 * (ends[ends > 0] - 1)[:, None] + np.arange(3)).reshape(-1)  # node 0 is dropped
        u = columns[1:].reshape(3 * (n - 1), -1)[rows]
        small = np.eye(u.shape[1]) + u.T @ t_u[rows]
        t_rhs = t_rhs - t_u @ np.linalg.solve(small, u.T @ t_rhs[rows])
    return np.vstack((np.zeros((1, 3)), t_rhs.reshape(n - 1, 3)))


def _dense_solve(
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    a: FloatArray,
    b: FloatArray,
    info: FloatArray,
    rhs: FloatArray,
) -> FloatArray:
    """H·dx = rhs with H assembled densely (node 0 fixed); for graphs that are not a chain plus loops."""
    n = len(rhs)
    at_o = np.transpose(a, (0, 2, 1)) @ info
    bt_o = np.transpose(b, (0, 2, 1)) @ info
    h = np.zeros((3 * n, 3 * n))
    k = np.arange(3)
    for rows, cols, blocks in ((i, i, at_o @ a), (i, j, at_o @ b), (j, i, bt_o @ a), (j, j, bt_o @ b)):
        r = (3 * rows[:, None, None] + k[None, :, None]) * np.ones((1, 1, 3), dtype=np.int64)
        c = (3 * cols[:, None, None] + k[None, None, :]) * np.ones((1, 3, 1), dtype=np.int64)
        np.add.at(h, (r, c), blocks)
    hm = h[3:, 3:]
    dx = np.linalg.lstsq(hm, rhs.reshape(-1)[3:], rcond=None)[0]
    return np.vstack((np.zeros((1, 3)), dx.reshape(n - 1, 3)))


def optimize(
    poses: FloatArray,
    edges: list[Edge],
    max_iterations: int = 10,
    tolerance: float = 1e-4,
    kernel_width: float = 1.0,
) -> FloatArray:
    """Gauss-Newton over all node poses (N, 3) with node 0 fixed; returns the optimised copy.

    Stops after ``max_iterations`` or once no pose moves by more than ``tolerance`` (m or rad).
    ``kernel_width`` is the Cauchy kernel's c (in standard deviations) applied to robust edges.
    """
    x = np.array(poses, dtype=np.float64, copy=True)
    n = len(x)
    if n < 2 or not edges:
        return x
    for e in edges:
        if not (0 <= e.i < n and 0 <= e.j < n) or e.i == e.j:
            raise ValueError(f"pose-graph edge ({e.i}, {e.j}) does not join two distinct nodes of {n}")
    i = np.array([e.i for e in edges], dtype=np.int64)
    j = np.array([e.j for e in edges], dtype=np.int64)
    z = np.array([e.z for e in edges], dtype=np.float64)
    info0 = np.stack([e.information for e in edges])
    robust = np.array([e.robust for e in edges], dtype=bool)
    cz, sz = np.cos(z[:, 2]), np.sin(z[:, 2])
    rz_t = np.stack((np.column_stack((cz, sz)), np.column_stack((-sz, cz))), axis=1)  # (E, 2, 2) = Rzᵀ
    for _ in range(max_iterations):
        err, a, b = _linearize(x, i, j, z, rz_t)
        info = info0 * robust_weights(err, info0, robust, kernel_width)[:, None, None]
        w = info @ err[:, :, None]
        gradient = _scatter(i, (np.transpose(a, (0, 2, 1)) @ w)[:, :, 0], n) + _scatter(
            j, (np.transpose(b, (0, 2, 1)) @ w)[:, :, 0], n
        )
        dx = _solve_normal_equations(i, j, a, b, info, -gradient)
        x += dx
        x[:, 2] = normalize_angles(x[:, 2])
        if float(np.abs(dx).max()) < tolerance:
            break
    return x
