"""Where sm_dance_bot dances in turtlebot3_world, and how far: every figure that differs from SMACC2's.

SMACC2's sm_dance_bot runs in its own large Gazebo room (waypoints up to 13 m from the origin, rays of
4-5 m, F and S patterns of 9 iterations over several metres). turtlebot3_world is a hexagon of 2.9 m
circumradius with 3 × 3 pillars (radius 0.15 m, at x, y ∈ {-1.1, 0, 1.1}); the waffle's radius is
0.22 m and the largest free disk has a radius of 0.78 m (at (-2.0, 0.0)). So every goal below lies in
free space at least 0.57 m from a wall or pillar, and every straight motion of the patterns keeps at
least 0.34 m (the robot's radius plus 0.12 m) between the robot's centre and any obstacle (figures from
maps/turtlebot3_world.pgm), when the robot stands on the waypoint. Nav2's goal checker stops it up to
0.25 m short (``xy_goal_tolerance``), so a figure may still come too close to an obstacle: the behavior
server then refuses the motion (collision look-ahead), the state's failure transition goes on, and the
loop still runs its iterations. Distances are in m, angles in rad unless named ``_deg``, map frame.

Changes from SMACC2 (params/move_base_client/waypoints_plan.yaml and the superstates' constants):

* Waypoints 0-6 (upstream (3, -2), (-5.75, 3.5), (-10.25, -4.25), (2, -8.58), (-10, 13.5), (0, 0),
  (6, 8), mostly outside this map; (0, 0) is the centre pillar) become the pattern sites below:
  0 the free disk west of the pillars (radial 1), 1 the square between pillars (-1.1, 0), (0, 0),
  (-1.1, 1.1), (0, 1.1) (radial 2), 2 the strip north of the pillars (radial 3), 3 the strip south of
  them, east of the middle pillar (F pattern), 4 and 5 the space east of the pillars (pass-through
  legs), 6 the north strip's west end (S pattern).
* StNavigateToWaypoint1's goal (upstream (0, 0, 0), inside the centre pillar) is the spawn pose.
* Rays: radial 1 upstream 2 × 4 m → 2 × 0.4 m; radial 2 4 × 5 m → 4 × 0.3 m (a square between pillars
  has 0.64 m of clearance); radial 3 2 × 4 m → 2 × 0.4 m.
* F pattern: ray 3.25 → 0.3 m, pitch 0.75 → 0.25 m, 9 → 2 iterations, in the south-east corner.
* S pattern: pitch1 0.75 → 0.3 m, pitch2 1.45 → 0.25 m, 9 → 2 iterations (the north strip between the
  pillars' row and the wall is 0.9 m deep).
* Straight top-level motions: StNavigateForward1 1 → 0.4 m, StNavigateForward2 1 → 0.3 m,
  StNavigateReverse1 and 2: 2 → 0.3 m, StNavigateReverse3 2 → 0.15 m (it backs towards the north wall),
  StNavigateReverse4 0.5 → 0.3 m. Rotations keep SMACC2's angles.

A whole run takes 4 to 5.5 minutes of sim time (bench/bench_dance_bot.py: median 284 s over 3 runs).
"""

from __future__ import annotations

import math

from smacc_py.clients.cl_nav2z import Waypoint

#: The waypoint plan of StNavigateToWaypointsX (SMACC2: waypoints_plan.yaml), in order.
WAYPOINTS: tuple[Waypoint, ...] = (
    Waypoint(-2.0, 0.0, 0.0, "radial_1"),
    Waypoint(-0.55, 0.55, 0.0, "radial_2"),
    Waypoint(0.55, 1.75, 0.0, "radial_3"),
    Waypoint(0.45, -1.75, 0.0, "f_pattern"),
    Waypoint(1.7, -0.55, math.pi / 2, "east_1"),
    Waypoint(1.7, 0.0, 0.0, "east_2"),
    Waypoint(-0.75, 1.85, 0.0, "s_pattern"),
)
#: StNavigateToWaypoint1's goal: back to the spawn pose.
HOME = (-2.0, -0.5, 0.0)

#: Radial patterns: (rays, ray length m). SMACC2: total_iterations(), ray_length_meters().
RADIAL_1 = (2, 0.4)
RADIAL_2 = (4, 0.3)
RADIAL_3 = (2, 0.4)
#: F pattern: ray length, pitch (m), iterations. SMACC2: ray_lenght_meters(), pitch_lenght_meters().
F_RAY, F_PITCH, F_ITERATIONS = 0.3, 0.25, 2
#: S pattern: pitch1, pitch2 (m), iterations. SMACC2: pitch1_lenght_meters(), pitch2_lenght_meters().
S_PITCH_1, S_PITCH_2, S_ITERATIONS = 0.3, 0.25, 2
#: Straight top-level motions (m).
FORWARD_1, FORWARD_2 = 0.4, 0.3
REVERSE_1, REVERSE_2, REVERSE_3, REVERSE_4 = 0.3, 0.3, 0.15, 0.3
#: Forward speed of every straight motion (m/s; the waffle's limit is 0.26).
FORWARD_SPEED = 0.25
