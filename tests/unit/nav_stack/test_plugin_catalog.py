"""The catalog nav-bringup checks files against says what the servers' factories build, no more, no less.

If a server gains a plugin type and the catalog does not (or the reverse), nav-bringup would refuse
a file the stack can run (or start a stack that refuses it at configure). These tests keep the two
in step.
"""

from __future__ import annotations

import pytest

from nav_stack.core.collision_monitor.params import POLYGON_TYPES
from nav_stack.ros.behaviors import behavior_server
from nav_stack.ros.bringup import bringup_components
from nav_stack.ros.bringup.plugin_catalog import (
    AVAILABLE_NODES,
    BEHAVIORS,
    COLLISION_POLYGONS,
    CONTROLLERS,
    DOCKS,
    NAVIGATION_NODES,
    PLANNERS,
    PLUGIN_LISTS,
    SMOOTHERS,
    class_name,
)
from nav_stack.ros.control import controller_plugins
from nav_stack.ros.docking import docking_plugins
from nav_stack.ros.planning import planner_server, smoother_server


@pytest.mark.parametrize(("catalog", "factory"), [
    (CONTROLLERS, controller_plugins.CONTROLLER_TYPES),
    (PLANNERS, planner_server.PLANNER_TYPES),
    (BEHAVIORS, behavior_server.BEHAVIOR_TYPES),
    (SMOOTHERS, smoother_server.SMOOTHER_TYPES),
    (DOCKS, docking_plugins.PLUGIN_TYPES),
    (COLLISION_POLYGONS, POLYGON_TYPES),
], ids=["controllers", "planners", "behaviors", "smoothers", "docks", "collision_polygons"])
def test_each_plugin_list_names_what_its_factory_builds(catalog: tuple[str, ...], factory: object) -> None:
    assert sorted(catalog) == sorted(factory)  # type: ignore[call-overload]


def test_bringup_can_build_every_server_it_says_it_has() -> None:
    builders = bringup_components._server_builders(None)
    assert set(builders) == set(AVAILABLE_NODES)
    # Every server of Jazzy's navigation launch file is here now.
    assert set(NAVIGATION_NODES) <= AVAILABLE_NODES


def test_ids_the_factories_type_by_default_are_the_catalogs_defaults() -> None:
    """An id whose ``.plugin`` the file leaves out: catalog and factory give it the same type."""
    defaults = {(spec.node, plugin_id): kind
                for spec in PLUGIN_LISTS for plugin_id, kind in spec.default_types}
    factories = [("controller_server", controller_plugins.DEFAULT_TYPES),
                 ("behavior_server", behavior_server.DEFAULT_TYPES),
                 ("planner_server", planner_server.DEFAULT_PLUGIN),
                 ("smoother_server", smoother_server.DEFAULT_PLUGIN)]
    for node, table in factories:
        for plugin_id, plugin_type in table.items():
            assert defaults.get((node, plugin_id)) == class_name(plugin_type), (node, plugin_id)
