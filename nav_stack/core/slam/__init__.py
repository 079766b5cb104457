"""Grid SLAM (numpy + two numba kernels): log-odds mapping, correlative scan matching, loop closure.

Typical use (the SLAM node feeds every LaserScan with the odometry pose at its stamp)::

    slam = GridSlam(SlamParams(map_start_pose=(-2.0, -0.5, 0.0)))
    update = slam.process(scan, odom_pose, stamp, laser_pose)   # publish update.map_to_odom
    occupancy, spec = slam.occupancy(complete=False)            # publish /map every map_update_interval
    write_graph(slam.graph(), "office")                         # office.posegraph + office.data
    again = GridSlam.from_graph(read_graph("office"))           # continue it (restart_at a pose) ...
    here = GraphLocalizer.from_graph(read_graph("office"))      # ... or only localize on it
"""

from nav_stack.core.slam.correlation import CorrelationGrid, MatchResult, SearchWindow, match
from nav_stack.core.slam.laser import ScanPoints, scan_points
from nav_stack.core.slam.localization import GraphLocalizer, resume
from nav_stack.core.slam.log_odds import LogOddsGrid
from nav_stack.core.slam.mapper import GridSlam
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.pose_graph import Edge, optimize, total_error
from nav_stack.core.slam.serialization import GraphFileError, SlamGraph, read_graph, write_graph
from nav_stack.core.slam.shared import SlamUpdate, between, inverse

__all__ = [
    "CorrelationGrid",
    "Edge",
    "GraphFileError",
    "GraphLocalizer",
    "GridSlam",
    "LogOddsGrid",
    "MatchResult",
    "ScanPoints",
    "SearchWindow",
    "SlamGraph",
    "SlamParams",
    "SlamUpdate",
    "between",
    "inverse",
    "match",
    "optimize",
    "read_graph",
    "resume",
    "scan_points",
    "total_error",
    "write_graph",
]
