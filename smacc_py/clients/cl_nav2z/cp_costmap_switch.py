"""``CpCostmapSwitch``: turn costmap layers on and off at run time (SMACC2's CostmapSwitch).

Why: a state may need the robot to ignore a layer for a while, e.g. the obstacle layer while it
docks against a wall. Every Nav2 costmap layer has a boolean ``<layer>.enabled`` parameter that the
layer reads again when it changes (ROS 1's dynamic reconfigure, which SMACC2 aimed at and left as
"not implemented" in ROS 2). This component sets it through the costmap node's
``<node>/set_parameters`` service (rcl_interfaces/srv/SetParameters).

A layer is named ``<costmap>/<layer>`` (``global_costmap/obstacle_layer``); its node is
``/<costmap>/<costmap>``, where Nav2 (and nav_stack) run each costmap. ``StandardLayers`` names
Nav2's usual four; other layers are added with ``register_layer``. Requests never block: the answer
arrives through ``on_done(succeeded, detail)`` on the executor thread, and ``enabled`` keeps the last
value each layer accepted.
"""

from __future__ import annotations

import enum
import logging
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters

from smacc_py.clients.cl_nav2z.service_caller import DEFAULT_CALL_TIMEOUT_S, ServiceCaller
from smacc_py.ros.components.checks import check_duration
from smacc_py.ros.components.service_call import ServiceCall

_log = logging.getLogger("smacc_py")

#: ``on_done(succeeded, detail)``: detail is empty on success, else why the layer was not switched.
SwitchDoneCallback = Callable[[bool, str], None]


class StandardLayers(enum.Enum):
    """Nav2's default layer names (SMACC2: ``CostmapSwitch::StandardLayers``)."""

    GLOBAL_OBSTACLES_LAYER = "global_costmap/obstacle_layer"
    LOCAL_OBSTACLES_LAYER = "local_costmap/obstacle_layer"
    GLOBAL_INFLATED_LAYER = "global_costmap/inflation_layer"
    LOCAL_INFLATED_LAYER = "local_costmap/inflation_layer"


LayerName = str | StandardLayers


@dataclass(frozen=True)
class CostmapLayer:
    """Where a layer's switch lives: ``parameter`` of ``node`` (set through ``node``/set_parameters)."""

    node: str
    parameter: str

    @property
    def service(self) -> str:
        """The node's SetParameters service."""
        return f"{self.node}/set_parameters"


def layer_key(layer: LayerName) -> str:
    """The ``<costmap>/<layer>`` spelling of ``layer`` (leading and trailing slashes dropped)."""
    return (layer.value if isinstance(layer, StandardLayers) else str(layer)).strip("/")


def parse_layer(owner: str, layer: LayerName, enable_property: str = "enabled") -> tuple[str, CostmapLayer]:
    """(``<costmap>/<layer>``, its CostmapLayer); ValueError naming ``owner`` and the value if malformed."""
    parts = layer_key(layer).split("/") if isinstance(layer, (str, StandardLayers)) else []
    if len(parts) != 2 or not all(parts) or not enable_property:
        raise ValueError(f"{owner}: layer must be '<costmap>/<layer>' (e.g. 'global_costmap/obstacle_layer') "
                         f"with a non-empty enable property, got {layer!r} and {enable_property!r}")
    costmap, plugin = parts
    return f"{costmap}/{plugin}", CostmapLayer(f"/{costmap}/{costmap}", f"{plugin}.{enable_property}")


class CpCostmapSwitch(ServiceCaller):
    """Switches the registered costmap layers.

    Args:
        layers: the layers known from the start (default: the four ``StandardLayers``).
        timeout_s: s (machine and wall clock) a request may take, discovery included.

    Attributes:
        enabled: ``<costmap>/<layer>`` → the value its node last accepted (absent until then).
    """

    def __init__(self, layers: Iterable[LayerName] = tuple(StandardLayers),
                 timeout_s: float = DEFAULT_CALL_TIMEOUT_S) -> None:
        super().__init__()
        self.timeout_s = check_duration("CpCostmapSwitch", "timeout_s", timeout_s)
        self.layers: dict[str, CostmapLayer] = dict(parse_layer("CpCostmapSwitch", layer) for layer in layers)
        self.enabled: dict[str, bool] = {}
        self._clients: dict[str, Any] = {}  # SetParameters service → client
        self._initialized = False

    def on_initialize(self) -> None:
        self._initialized = True
        for layer in self.layers.values():
            self._client_for(layer)

    def _client_for(self, layer: CostmapLayer) -> Any:
        if layer.service not in self._clients:
            self._clients[layer.service] = self.make_client(SetParameters, layer.service)
        return self._clients[layer.service]

    def register_layer(self, layer: LayerName, enable_property: str = "enabled") -> str:
        """Make another layer switchable (SMACC2: ``registerProxyFromDynamicReconfigureServer``);
        returns its ``<costmap>/<layer>`` name."""
        name, where = parse_layer("CpCostmapSwitch", layer, enable_property)
        self.layers[name] = where
        if self._initialized:
            self._client_for(where)
        return name

    def exists(self, layer: LayerName) -> bool:
        """True when ``layer`` is registered."""
        return layer_key(layer) in self.layers

    def enable(self, layer: LayerName, on_done: SwitchDoneCallback | None = None) -> ServiceCall:
        """Turn ``layer`` on (see ``set_layer_enabled``)."""
        return self.set_layer_enabled(layer, True, on_done)

    def disable(self, layer: LayerName, on_done: SwitchDoneCallback | None = None) -> ServiceCall:
        """Turn ``layer`` off (see ``set_layer_enabled``)."""
        return self.set_layer_enabled(layer, False, on_done)

    def set_layer_enabled(self, layer: LayerName, enabled: bool,
                          on_done: SwitchDoneCallback | None = None) -> ServiceCall:
        """Set ``layer``'s enable parameter; never blocks. ValueError, sending nothing, for a layer that
        is not registered (naming it and the registered ones)."""
        name = layer_key(layer)
        where = self.layers.get(name)
        if where is None:
            raise ValueError(f"CpCostmapSwitch: layer {layer!r} is not registered; registered: "
                             f"{sorted(self.layers)} (add it with register_layer)")
        value = ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=bool(enabled))
        request = SetParameters.Request(parameters=[Parameter(name=where.parameter, value=value)])
        done = on_done or (lambda _ok, _detail: None)

        def answered(response: Any) -> None:
            result = response.results[0] if response.results else None
            if result is not None and result.successful:
                self.enabled[name] = bool(enabled)
                done(True, "")
            else:
                reason = result.reason if result is not None else "no result in the response"
                done(False, f"CpCostmapSwitch: {where.node} refused {where.parameter}={enabled}: {reason}")

        _log.info("CpCostmapSwitch: %s %s", "enabling" if enabled else "disabling", name)
        return self.call_service(self._client_for(where), request, service_name=where.service,
                                 timeout_s=self.timeout_s, on_response=answered,
                                 on_failure=lambda reason: done(False, f"CpCostmapSwitch: {reason}"))
