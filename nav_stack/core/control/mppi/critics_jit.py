"""critics.py and path_critics.py compiled with numba: the same critics, a loop per trajectory.

Every function mirrors its namesake in the reference modules (which say what each critic means);
tests/unit/nav_stack/test_mppi_jit.py checks that they agree. ``score`` runs the critics of a cycle:
their parameters arrive as one row of floats each (packing.FIELDS names them), the cycle's scalars
as ``ctx`` (the C_* indices).

Why one module for all of them: numba's on-disk cache (``cache=True``) checks only the source file of
the function it loads, so a compiled ``score`` cached in another file would go on calling the old
critics after an edit here. Kernels that call each other therefore share a file; the Python code
around them (packing.py, kernels_jit.py) may live elsewhere.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from numba import njit

F64 = npt.NDArray[np.float64]
U8 = npt.NDArray[np.uint8]

# ctx: the cycle's scalars
C_ROBOT_X, C_ROBOT_Y, C_ROBOT_YAW, C_GOAL_X, C_GOAL_Y, C_GOAL_YAW = 0, 1, 2, 3, 4, 5
C_DT, C_VX_MAX, C_VX_MIN, C_VY_MAX, C_MIN_TURNING_R, C_GOAL_DIST_TOL = 6, 7, 8, 9, 10, 11
C_CIRCUMSCRIBED, C_INSCRIBED, C_MODEL = 12, 13, 14
CTX_SIZE = 15
OMNI, ACKERMANN = 1, 2
STRAIGHT_WZ = 1e-6  # as critics.STRAIGHT_WZ
NO_INFORMATION, LETHAL, INSCRIBED = 255.0, 254.0, 253.0
TWO_PI = 2.0 * math.pi
#: critic name → the code score() switches on
CRITIC_CODES = {name: code for code, name in enumerate((
    "ConstraintCritic", "CostCritic", "ObstaclesCritic", "GoalCritic", "GoalAngleCritic",
    "PathAlignCritic", "PathFollowCritic", "PathAngleCritic", "PreferForwardCritic", "TwirlingCritic"))}
(CONSTRAINT, COST, OBSTACLES, GOAL, GOAL_ANGLE, PATH_ALIGN, PATH_FOLLOW, PATH_ANGLE, PREFER_FORWARD,
 TWIRLING) = range(10)
DISABLED = -1


@njit(cache=True, error_model="numpy", inline="always")
def angle_diff(to: float, frm: float) -> float:
    """nav_stack.core.geometry.angle_diff compiled for the kernels (numba cannot call the Python one)."""
    d = to - frm
    return d - TWO_PI * math.floor((d + math.pi) / TWO_PI)


@njit(cache=True, error_model="numpy", inline="always")
def powered(term: float, weight: float, power: int) -> float:
    return (term * weight) ** power if power > 1 else term * weight


@njit(cache=True, error_model="numpy", inline="always")
def goal_within(ctx: F64, distance: float) -> bool:
    dx, dy = ctx[C_ROBOT_X] - ctx[C_GOAL_X], ctx[C_ROBOT_Y] - ctx[C_GOAL_Y]
    return bool(dx * dx + dy * dy < distance * distance)


@njit(cache=True, error_model="numpy", inline="always")
def cell_cost(costs: U8, gm: F64, px: float, py: float) -> float:
    """GridSpec.world_to_cell + CostGrid.cost_at for one point: 255 off the grid."""
    dx, dy = px - gm[0], py - gm[1]
    if gm[4] != 0.0:
        dx, dy = gm[3] * dx + gm[4] * dy, -gm[4] * dx + gm[3] * dy
    mx, my = math.floor(dx / gm[2]), math.floor(dy / gm[2])
    if mx < 0 or my < 0 or mx >= costs.shape[1] or my >= costs.shape[0]:
        return NO_INFORMATION
    return float(costs[int(my), int(mx)])


@njit(cache=True, error_model="numpy")
def footprint_cost(costs: U8, gm: F64, outline: F64, x: float, y: float, yaw: float) -> float:
    """critics.footprint_cost for one pose (not inlined: rarely needed, and inlining its loop into
    the critics' loops made them several times slower)."""
    if outline.shape[0] == 0:
        return cell_cost(costs, gm, x, y)
    c, s = math.cos(yaw), math.sin(yaw)
    worst = 0.0
    for k in range(outline.shape[0]):
        ox, oy = outline[k, 0], outline[k, 1]
        worst = max(worst, cell_cost(costs, gm, x + c * ox - s * oy, y + s * ox + c * oy))
    return worst


@njit(cache=True, error_model="numpy", inline="always")
def needs_footprint(consider: bool, centre: float, possible: float) -> bool:
    """Whether the footprint's cost decides (critics._collision_costs): only where the centre's cost
    says some orientation could touch an obstacle."""
    return consider and centre >= 1.0 and centre != NO_INFORMATION and (centre >= possible or possible < 1.0)


@njit(cache=True, error_model="numpy", inline="always")
def collides(cost: float, consider: bool) -> bool:
    return cost >= LETHAL or (cost == INSCRIBED and not consider)


@njit(cache=True, error_model="numpy")
def cost_critic(prm: F64, ctx: F64, x: F64, y: F64, yaw: F64, costs: U8, gm: F64, outline: F64,
                out: F64) -> bool:
    weight, power, critical, near_collision = prm[0], int(prm[1]), prm[2], prm[3]
    consider, collision_cost, step = prm[4] != 0.0, prm[5], int(prm[7])
    near_goal = goal_within(ctx, prm[6])
    possible = ctx[C_CIRCUMSCRIBED]
    steps = x.shape[1]
    scale = weight / 254.0 / ((steps - 1) // step + 1)
    all_collide = True
    for i in range(x.shape[0]):
        total, hit = 0.0, False
        for j in range(0, steps, step):
            centre = cell_cost(costs, gm, x[i, j], y[i, j])
            if centre < 1.0:
                continue
            cost = centre
            if needs_footprint(consider, centre, possible):
                cost = footprint_cost(costs, gm, outline, x[i, j], y[i, j], yaw[i, j])
            if collides(cost, consider):
                total, hit = collision_cost, True
                break
            if centre >= near_collision:
                total += critical
            elif not near_goal:
                total += centre
        all_collide &= hit
        out[i] = powered(total, scale, power)
    return all_collide


@njit(cache=True, error_model="numpy")
def obstacles_critic(prm: F64, ctx: F64, x: F64, y: F64, yaw: F64, costs: U8, gm: F64, outline: F64,
                     out: F64) -> bool:
    power, consider, critical_weight, repulsion_weight = int(prm[0]), prm[1] != 0.0, prm[2], prm[3]
    collision_cost, margin, inflation_radius, k = prm[4], prm[5], prm[7], prm[8]
    near_goal = goal_within(ctx, prm[6])
    inscribed, possible = ctx[C_INSCRIBED], ctx[C_CIRCUMSCRIBED]
    batch, steps = x.shape
    raw, repulsive = np.zeros(batch), np.zeros(batch)
    all_collide = True
    for i in range(batch):
        critical, repulsion, hit = 0.0, 0.0, False
        for j in range(steps):
            centre = cell_cost(costs, gm, x[i, j], y[i, j])
            cost, used = centre, needs_footprint(consider, centre, possible)
            if used:
                cost = footprint_cost(costs, gm, outline, x[i, j], y[i, j], yaw[i, j])
            if cost < 1.0:
                continue
            if collides(cost, consider):
                hit = True
                break
            if inflation_radius == 0.0 or k == 0.0:
                continue
            dist = (k * inscribed - math.log(cost) + math.log(INSCRIBED)) / k
            if not used:
                dist -= inscribed
            if dist < margin:
                critical += margin - dist
            if not near_goal:
                repulsion += inflation_radius - dist
        all_collide &= hit
        raw[i] = collision_cost if hit else critical
        repulsive[i] = repulsion
    lowest = repulsive.min()
    for i in range(batch):
        out[i] = powered(critical_weight * raw[i] + repulsion_weight * ((repulsive[i] - lowest) / steps), 1.0,
                         power)
    return all_collide


@njit(cache=True, error_model="numpy")
def constraint_critic(prm: F64, ctx: F64, vx: F64, vy: F64, wz: F64, out: F64) -> None:
    weight, power, dt = prm[0], int(prm[1]), ctx[C_DT]
    model, min_turning_r = int(ctx[C_MODEL]), ctx[C_MIN_TURNING_R]
    max_vel = math.hypot(ctx[C_VX_MAX], ctx[C_VY_MAX])
    min_vel = math.copysign(math.hypot(ctx[C_VX_MIN], ctx[C_VY_MAX]), 1.0 if ctx[C_VX_MIN] > 0.0 else -1.0)
    for i in range(vx.shape[0]):
        total = 0.0
        for j in range(vx.shape[1]):
            speed = vx[i, j]
            if model == OMNI:
                speed = math.copysign(1.0, speed) * math.hypot(vx[i, j], vy[i, j])
            beyond = max(speed - max_vel, 0.0) + max(min_vel - speed, 0.0)
            if model == ACKERMANN:
                turn = abs(wz[i, j])
                beyond += max(min_turning_r - abs(vx[i, j]) / turn, 0.0) if turn > STRAIGHT_WZ else 0.0
            total += beyond * dt
        out[i] = powered(total, weight, power)


@njit(cache=True, error_model="numpy")
def goal_critic(prm: F64, ctx: F64, x: F64, y: F64, out: F64) -> None:
    if not goal_within(ctx, prm[2]):
        return
    gx, gy = ctx[C_GOAL_X], ctx[C_GOAL_Y]
    for i in range(x.shape[0]):
        total = 0.0
        for j in range(x.shape[1]):
            total += math.hypot(x[i, j] - gx, y[i, j] - gy)
        out[i] = powered(total / x.shape[1], prm[0], int(prm[1]))


@njit(cache=True, error_model="numpy")
def goal_angle_critic(prm: F64, ctx: F64, yaw: F64, out: F64) -> None:
    if not goal_within(ctx, prm[2]):
        return
    for i in range(yaw.shape[0]):
        total = 0.0
        for j in range(yaw.shape[1]):
            total += abs(angle_diff(yaw[i, j], ctx[C_GOAL_YAW]))
        out[i] = powered(total / yaw.shape[1], prm[0], int(prm[1]))


@njit(cache=True, error_model="numpy")
def prefer_forward_critic(prm: F64, ctx: F64, vx: F64, out: F64) -> None:
    if goal_within(ctx, prm[2]):
        return
    for i in range(vx.shape[0]):
        total = 0.0
        for j in range(vx.shape[1]):
            total += max(-vx[i, j], 0.0) * ctx[C_DT]
        out[i] = powered(total, prm[0], int(prm[1]))


@njit(cache=True, error_model="numpy")
def twirling_critic(prm: F64, ctx: F64, wz: F64, out: F64) -> None:
    if goal_within(ctx, ctx[C_GOAL_DIST_TOL]):
        return
    for i in range(wz.shape[0]):
        total = 0.0
        for j in range(wz.shape[1]):
            total += abs(wz[i, j])
        out[i] = powered(total / wz.shape[1], prm[0], int(prm[1]))


# -- the path critics (path_critics.py) ---------------------------------------------------------------
NO_DIRECTIONAL_PREFERENCE, CONSIDER_FEASIBLE_PATH_ORIENTATIONS = 1, 2
HALF_PI = 0.5 * math.pi


@njit(cache=True, error_model="numpy")
def furthest_reached(x: F64, y: F64, path: F64) -> int:
    """path_critics.CycleFacts.furthest_reached."""
    furthest, last = 0, x.shape[1] - 1
    for i in range(x.shape[0]):
        ex, ey = x[i, last], y[i, last]
        best, best_j = math.inf, 0
        for j in range(furthest, path.shape[0]):
            dx, dy = ex - path[j, 0], ey - path[j, 1]
            d2 = dx * dx + dy * dy
            if d2 < best:
                best, best_j = d2, j
        furthest = max(furthest, best_j)
    return furthest


@njit(cache=True, error_model="numpy")
def path_valid(costs: U8, gm: F64, path: F64) -> npt.NDArray[np.bool_]:
    """path_critics.CycleFacts.path_valid."""
    valid = np.zeros(max(path.shape[0] - 1, 0), dtype=np.bool_)
    for k in range(valid.shape[0]):
        valid[k] = cell_cost(costs, gm, path[k, 0], path[k, 1]) < INSCRIBED
    return valid


@njit(cache=True, error_model="numpy", inline="always")
def closest_path_point(along: F64, dist: float, start: int) -> int:
    """path_critics.closest_path_point for one trajectory."""
    n = along.shape[0]
    i = start + 1
    while i < n and along[i] <= dist:
        i += 1
    if i >= n:
        return int(n - 1)
    return int(i - 1 if dist - along[i - 1] < along[i] - dist else i)


@njit(cache=True, error_model="numpy")
def occupied(valid: npt.NDArray[np.bool_], furthest: int, ratio: float) -> bool:
    blocked = 0
    for k in range(furthest):
        if not valid[k]:
            blocked += 1
        if blocked / max(furthest, 1) > ratio and blocked > 2:
            return True
    return False


@njit(cache=True, error_model="numpy")
def path_align_critic(prm: F64, ctx: F64, x: F64, y: F64, yaw: F64, path: F64, valid: npt.NDArray[np.bool_],
                      furthest: int, out: F64) -> None:
    weight, power, ratio, step = prm[0], int(prm[1]), prm[2], int(prm[3])
    use_orientations = prm[6] != 0.0
    n = path.shape[0]
    if n < 2 or furthest < max(prm[5], 1.0) or goal_within(ctx, prm[4]) or occupied(valid, furthest, ratio):
        return
    along = np.zeros(furthest)
    for k in range(1, furthest):
        dx, dy = path[k, 0] - path[k - 1, 0], path[k, 1] - path[k - 1, 1]
        along[k] = along[k - 1] + math.sqrt(dx * dx + dy * dy)
    for i in range(x.shape[0]):
        total, count, travelled, nearest = 0.0, 0, 0.0, 0
        px, py = x[i, 0], y[i, 0]
        for j in range(step, x.shape[1], step):
            dx, dy = x[i, j] - px, y[i, j] - py
            px, py = x[i, j], y[i, j]
            travelled += math.sqrt(dx * dx + dy * dy)
            nearest = closest_path_point(along, travelled, nearest)
            if valid[nearest]:
                ex, ey = path[nearest, 0] - px, path[nearest, 1] - py
                d2 = ex * ex + ey * ey
                if use_orientations:
                    turn = angle_diff(yaw[i, j], path[nearest, 2])
                    d2 = d2 + turn * turn
                total += math.sqrt(d2)
                count += 1
        out[i] = powered(total / count if count > 0 else 0.0, weight, power)


@njit(cache=True, error_model="numpy")
def path_follow_critic(prm: F64, ctx: F64, x: F64, y: F64, path: F64, valid: npt.NDArray[np.bool_],
                       furthest: int, out: F64) -> None:
    n = path.shape[0]
    if n < 2 or goal_within(ctx, prm[3]):
        return
    last = n - 1
    index = min(furthest + int(prm[2]), last)
    while index < last - 1 and not valid[index]:
        index += 1
    tx, ty = path[index, 0], path[index, 1]
    end = x.shape[1] - 1
    for i in range(x.shape[0]):
        ex, ey = x[i, end] - tx, y[i, end] - ty
        out[i] = powered(math.sqrt(ex * ex + ey * ey), prm[0], int(prm[1]))


@njit(cache=True, error_model="numpy", inline="always")
def heading_error(mode: int, yaw: float, bearing: float, path_yaw: float) -> float:
    """path_critics.heading_error."""
    if mode == NO_DIRECTIONAL_PREFERENCE:
        return min(abs(angle_diff(yaw, bearing)), abs(angle_diff(yaw + math.pi, bearing)))
    if mode == CONSIDER_FEASIBLE_PATH_ORIENTATIONS and abs(angle_diff(path_yaw, bearing)) > HALF_PI:
        bearing += math.pi
    return abs(angle_diff(yaw, bearing))


@njit(cache=True, error_model="numpy")
def path_angle_critic(prm: F64, ctx: F64, x: F64, y: F64, yaw: F64, path: F64, furthest: int,
                      out: F64) -> None:
    if goal_within(ctx, prm[3]):
        return
    k = min(furthest + int(prm[2]), path.shape[0] - 1)
    tx, ty, tyaw = path[k, 0], path[k, 1], path[k, 2]
    mode = int(prm[5])
    bearing = math.atan2(ty - ctx[C_ROBOT_Y], tx - ctx[C_ROBOT_X])
    if heading_error(mode, ctx[C_ROBOT_YAW], bearing, tyaw) < prm[4]:
        return
    for i in range(x.shape[0]):
        total = 0.0
        for j in range(x.shape[1]):
            b = math.atan2(ty - y[i, j], tx - x[i, j])
            flip = (mode == NO_DIRECTIONAL_PREFERENCE and abs(angle_diff(b, yaw[i, j])) >= HALF_PI) or (
                mode == CONSIDER_FEASIBLE_PATH_ORIENTATIONS and abs(angle_diff(tyaw, b)) >= HALF_PI)
            if flip:
                b = angle_diff(b + math.pi, 0.0)
            total += abs(angle_diff(b, yaw[i, j]))
        out[i] = powered(total / x.shape[1], prm[0], int(prm[1]))


@njit(cache=True, error_model="numpy")
def score(codes: npt.NDArray[np.int64], table: F64, ctx: F64, x: F64, y: F64, yaw: F64, vx: F64, vy: F64,
          wz: F64, costs: U8, gm: F64, outline: F64, path: F64, out: F64) -> bool:
    """critics.evaluate: every critic's cost into ``out`` (C, B); whether all trajectories collide."""
    out[:] = 0.0
    furthest, needs_valid, needs_furthest = 0, False, False
    for code in codes:
        needs_valid |= code in (PATH_ALIGN, PATH_FOLLOW)
        needs_furthest |= code in (PATH_ALIGN, PATH_FOLLOW, PATH_ANGLE)
    if needs_furthest:
        furthest = furthest_reached(x, y, path)
    valid = path_valid(costs, gm, path) if needs_valid else np.zeros(0, dtype=np.bool_)
    fail = False
    for k in range(codes.shape[0]):
        code, prm, o = codes[k], table[k], out[k]
        if code == CONSTRAINT:
            constraint_critic(prm, ctx, vx, vy, wz, o)
        elif code == COST:
            fail = cost_critic(prm, ctx, x, y, yaw, costs, gm, outline, o)
        elif code == OBSTACLES:
            fail = obstacles_critic(prm, ctx, x, y, yaw, costs, gm, outline, o)
        elif code == GOAL:
            goal_critic(prm, ctx, x, y, o)
        elif code == GOAL_ANGLE:
            goal_angle_critic(prm, ctx, yaw, o)
        elif code == PATH_ALIGN:
            path_align_critic(prm, ctx, x, y, yaw, path, valid, furthest, o)
        elif code == PATH_FOLLOW:
            path_follow_critic(prm, ctx, x, y, path, valid, furthest, o)
        elif code == PATH_ANGLE:
            path_angle_critic(prm, ctx, x, y, yaw, path, furthest, o)
        elif code == PREFER_FORWARD:
            prefer_forward_critic(prm, ctx, vx, o)
        elif code == TWIRLING:
            twirling_critic(prm, ctx, wz, o)
    return fail
