"""amcl's parameters: nav2_amcl's (AmclParams), the filter's random seed and the health thresholds.

Why a module of its own: the node only schedules; reading parameters has two quirks worth keeping
apart: Nav2's nested ``initial_pose.{x,y,z,yaw}`` spelling beside the flat one, and the seed.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from nav_stack.core.localization import AmclParams
from nav_stack.core.localization.health import HealthParams
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.lifecycle.node import NavLifecycleNode

DEFAULT_SEED = 0  # the particle filter's random seed unless ``random_seed`` says otherwise
HEALTH_PREFIX = "health."  # HealthParams fields are ``health.<field>`` under amcl


def load_params(node: NavLifecycleNode) -> AmclParams:
    """AmclParams from the node's parameters, reading Nav2's nested ``initial_pose.*`` names as well."""
    params = declare_dataclass(node, AmclParams)
    nested: dict[str, Any] = {}
    for axis in ("x", "y", "z", "yaw"):
        flat = f"initial_pose_{axis}"
        default = getattr(AmclParams, flat)
        name = f"initial_pose.{axis}"
        if not node.has_parameter(name):
            node.declare_parameter(name, float(default))
        value = float(node.get_parameter(name).value)
        if value != default:
            nested[flat] = value
    return dataclasses.replace(params, **nested)


def random_seed(node: NavLifecycleNode) -> int | None:
    """The filter's seed from the ``random_seed`` parameter; None (OS entropy) for a negative one."""
    if not node.has_parameter("random_seed"):
        node.declare_parameter("random_seed", DEFAULT_SEED)
    seed = int(node.get_parameter("random_seed").value)
    return None if seed < 0 else seed


def load_health_params(node: NavLifecycleNode) -> HealthParams:
    """The localization health thresholds from the node's ``health.*`` parameters."""
    return declare_dataclass(node, HealthParams, prefix=HEALTH_PREFIX)
