"""Which older scans a new scan may close a loop with (Karto's candidate rule), and the chain to match.

Why this rule: scans the current one is already tied to (through the running buffer or an earlier
closure) add nothing; a closure only helps against scans the graph reaches by a long way round.
So, as in Karto's ``FindPossibleLoopClosure``, the graph is walked from the current node over
nodes that all lie within ``loop_search_maximum_distance``; whatever that walk reaches is
excluded. Of the remaining near nodes, a run of at least ``loop_match_minimum_chain_size``
consecutive scans forms the reference the new scan is matched against; requiring a chain keeps
one stray scan from producing a closure.

How far to search, and what to believe: the match window is the pose-graph uncertainty between
the chain and the new scan (``search_half_extent``: the graph path between them, each link adding
its variance), so a well-anchored graph does not look metres away for a look-alike. A match must
then pass ``verified``: both responses over their thresholds and a distinct peak (the matcher's
covariance under ``loop_match_maximum_stddev``). A periodic or corridor-like place scores well at
several offsets and is rejected there rather than trusted to the penalty's tie-break.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam.correlation import MatchResult, SearchWindow
from nav_stack.core.slam.laser import ScanPoints, clouds_in_map
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.shared import match_scan


@dataclass(frozen=True)
class LoopMatch:
    """The match of the newest scan against a candidate chain: the matched pose and its covariance
    (``result``), the chain node nearest to it (``anchor``, the loop edge's other end), and whether
    it passed ``verified``."""

    anchor: int
    result: MatchResult
    accepted: bool


def search_loop(
    poses: FloatArray,
    adjacency: list[list[int]],
    scans: Sequence[ScanPoints],
    joined: Sequence[FloatArray],
    params: SlamParams,
    window: SearchWindow,
) -> LoopMatch | None:
    """Match the newest node (the last of ``poses``, (N, 3) map frame) against the nearest unlinked
    chain of older scans, within the graph's uncertainty between them; None when there is no chain
    or too few points to match. ``scans`` and ``joined`` (laser.joined_returns) are each node's
    returns; ``window`` is the loop search window whose half extent is replaced by the
    uncertainty's."""
    current = len(poses) - 1
    p = params
    chains = candidate_chains(
        poses, adjacency, current, p.loop_search_maximum_distance, p.loop_match_minimum_chain_size
    )
    if not chains:
        return None
    chain = chains[0]
    half = search_half_extent(graph_hops(adjacency, current, chain), p)
    reference = clouds_in_map([scan.hits for scan in scans], poses, chain)
    fine = clouds_in_map(joined, poses, chain)
    prior = Pose2D(*poses[current])
    result = match_scan(p, reference, scans[current].hits, prior, replace(window, half_extent=half), fine)
    if result is None:
        return None
    d = np.hypot(poses[chain, 0] - result.pose.x, poses[chain, 1] - result.pose.y)
    return LoopMatch(chain[int(np.argmin(d))], result, verified(result, p))


def linked_near_nodes(adjacency: list[list[int]], near: np.ndarray, start: int) -> set[int]:
    """Nodes reachable from ``start`` through edges whose nodes are all ``near`` (a boolean per node)."""
    reached = {start}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        for other in adjacency[node]:
            if other not in reached and near[other]:
                reached.add(other)
                queue.append(other)
    return reached


def candidate_chains(
    poses: FloatArray, adjacency: list[list[int]], current: int, max_distance: float, min_chain: int
) -> list[list[int]]:
    """Runs of consecutive older node indices near ``poses[current]`` and not already linked to it.

    Returned nearest first (by the closest node of each run); each run has at least ``min_chain`` nodes.
    """
    d = np.hypot(poses[:, 0] - poses[current, 0], poses[:, 1] - poses[current, 1])
    near = d < max_distance
    excluded = linked_near_nodes(adjacency, near, current)
    candidates = [k for k in np.flatnonzero(near[:current]).tolist() if k not in excluded]
    runs: list[list[int]] = []
    for k in candidates:
        if runs and k == runs[-1][-1] + 1:
            runs[-1].append(k)
        else:
            runs.append([k])
    chains = [run for run in runs if len(run) >= min_chain]
    chains.sort(key=lambda run: float(d[run].min()))
    return chains


def graph_hops(adjacency: list[list[int]], start: int, targets: list[int]) -> int:
    """Fewest edges on a graph path from ``start`` to any of ``targets`` (len(adjacency) if none)."""
    goal = set(targets)
    depth = {start: 0}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        if node in goal:
            return depth[node]
        for other in adjacency[node]:
            if other not in depth:
                depth[other] = depth[node] + 1
                queue.append(other)
    return len(adjacency)


def search_half_extent(hops: int, params: SlamParams) -> float:
    """Half side (m) of the loop-match window: three standard deviations of the position drift
    accumulated over ``hops`` links (``link_stddev_xy`` each, independent), kept between the
    running-buffer window and ``loop_search_space_dimension`` / 2."""
    sigma = params.link_stddev_xy * float(np.sqrt(max(hops, 1)))
    low = params.correlation_search_space_dimension / 2.0
    return float(np.clip(3.0 * sigma, low, params.loop_search_space_dimension / 2.0))


def verified(result: MatchResult | None, params: SlamParams) -> bool:
    """A loop match is accepted: strong coarse and fine responses and a distinct position peak."""
    return (
        result is not None
        and result.coarse_response >= params.loop_match_minimum_response_coarse
        and result.response >= params.loop_match_minimum_response_fine
        and result.position_stddev <= params.loop_match_maximum_stddev
    )
