"""nav2_mppi_controller::MPPIController for nav_stack's controller server (a LocalController).

Each cycle: cut the local path for the critics (local_path.py), describe the scene (robot, speed,
path, goal, costmap, footprint), let the optimizer compute the command, keep what the
visualisation needs. How the algorithm works is in optimizer.py, reference.py and critics.py.

What comes from the controller server rather than from Nav2's own machinery: the path arrives
pruned to the local costmap and in its frame, so no TF here; the goal the goal critics aim at is
the last pose of that path. Up to the costmap's edge it is the real goal; beyond it, the edge of a
rolling window centred on the robot lies at least half the window away (1.5 m for the TB3's 3 m
window), outside every goal critic's threshold_to_consider (1.4 m at most by default), so a cut path
end never counts as the goal. The server's odometry gives no lateral speed (vy = 0), and its
Twist2D no vy either: for the Omni model the lateral command is ``last_command[1]``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from nav_stack.core.control.base import CircleFootprint, CostGrid, Footprint, NoValidControl, Twist2D
from nav_stack.core.control.mppi.critic_params import CRITIC_PARAMS
from nav_stack.core.control.mppi.local_path import LocalPath
from nav_stack.core.control.mppi.optimizer import Optimizer
from nav_stack.core.control.mppi.params import AckermannConstraints, MPPIParams, TrajectoryVisualizerParams
from nav_stack.core.control.mppi.scene import FootprintModel, Scene
from nav_stack.core.geometry import FloatArray, Pose2D


class MPPIController:
    """The MPPI controller plugin.

    Args:
        params: controller-wide parameters (``<id>.*``).
        critic_params: each critic's parameters by name (``<id>.<Critic>.*``); a critic named in
            ``params.critics`` without an entry gets its defaults.
        footprint: the controller server's footprint (circle or polygon).
        ackermann: ``AckermannConstraints.*`` (the Ackermann model's turning radius).
        visualizer: ``TrajectoryVisualizer.*`` (how the ROS layer thins the drawn samples).
        inscribed_radius: the local costmap's inscribed radius (m).
        inflation: (inflation_radius m, cost_scaling_factor) of the local costmap's inflation layer,
            or None without one: the footprint check's shortcut and the ObstaclesCritic need them.
        rng: the noise's random generator; default: seeded from ``params.random_seed``.
        kernels: "jit" (compiled) or "reference" (numpy).
    """

    def __init__(self, params: MPPIParams | None = None, critic_params: Mapping[str, Any] | None = None,
                 footprint: Footprint | None = None, *, ackermann: AckermannConstraints | None = None,
                 visualizer: TrajectoryVisualizerParams | None = None, inscribed_radius: float = 0.22,
                 inflation: tuple[float, float] | None = (0.7, 3.0), rng: np.random.Generator | None = None,
                 kernels: str = "jit") -> None:
        self._params = params or MPPIParams()
        self.critic_params = dict(critic_params or {})
        self.ackermann = ackermann or AckermannConstraints()
        self.visualizer = visualizer or TrajectoryVisualizerParams()
        self.footprint: Footprint = footprint or CircleFootprint(inscribed_radius)
        self.footprint_model = FootprintModel.of(self.footprint, inscribed_radius, inflation)
        self._kernels = kernels
        self._rng = rng
        self.local_path = LocalPath()
        self.last_trajectory: FloatArray = np.zeros((0, 3))
        self.transformed_plan: FloatArray = np.zeros((0, 3))
        self.last_command = (0.0, 0.0, 0.0)
        self._build()

    @property
    def params(self) -> MPPIParams:
        return self._params

    @params.setter
    def params(self, params: MPPIParams) -> None:
        """New controller-wide parameters (``ros2 param set``): the optimizer starts over, as Nav2's does."""
        self._params = params
        self._build()

    def set_critic_params(self, name: str, params: Any) -> None:
        """New parameters for one critic; the optimizer starts over."""
        self.critic_params[name] = params
        self._build()

    def _build(self) -> None:
        p = self._params
        rng = self._rng or np.random.default_rng(None if p.random_seed < 0 else p.random_seed)
        critics = [(name, self.critic_params.get(name) or CRITIC_PARAMS[name]()) for name in p.critics]
        self.optimizer = Optimizer(p, critics, self.ackermann.min_turning_r, rng, self._kernels)

    def reset(self) -> None:
        """A new path: zero control sequence, fresh noise (Nav2's MPPIController::reset)."""
        self.optimizer.reset()
        self.local_path.reset()

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
        """This cycle's command; NoValidControl when every sampled trajectory collides."""
        if len(path) == 0:
            raise NoValidControl("empty local path")
        plan, goal = self.local_path.cut(np.asarray(path, dtype=np.float64), robot, self._params)
        scene = Scene.make(robot, velocity, plan, goal, grid, self.footprint_model)
        self.transformed_plan = scene.path
        vx, vy, wz = self.optimizer.eval_control(scene)
        self.last_command = (vx, vy, wz)
        self.last_trajectory = self.optimizer.optimal_trajectory
        return Twist2D(vx, wz)

    @property
    def sampled_trajectories(self) -> tuple[FloatArray, FloatArray]:
        """x, y (B, T) of the last cycle's samples (the visualisation thins them)."""
        r = self.optimizer.rollouts
        return r.x, r.y
