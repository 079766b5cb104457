"""The dead-code guard's allowlist: names only a framework uses, which vulture cannot see.

vulture (pyproject.toml ``[tool.vulture]``) reads this file as code: each attribute below counts as a
use of that name. One statement per framework convention, each with its reason; the naming
conventions (pytest hooks, SMACC2 state names, ``on_exit_<TAG>``) are ``ignore_names`` patterns in
pyproject.toml instead. Add a name here only when a framework calls or reads it; dead code goes.
"""

# ruff: noqa: B018
from typing import Any

_: Any = None

# 1. rclpy's LifecycleNode calls these transition callbacks by name (nav_stack/ros/lifecycle/node.py).
(_.on_configure, _.on_cleanup, _.on_shutdown, _.on_error)

# 2. ROS message fields we fill for the subscriber at the other end of a topic (or, for _check_fields
#    and _header, the generated class's own slots, written directly on the hot path).
(_.map_load_time, _.update_time, _.time_increment, _.scan_time, _.capacity, _.design_capacity,
 _.power_supply_technology, _.instance_id, _.heartbeat_timeout, _.heartbeat_period, _.do_rectify,
 _._check_fields, _._header)

# 3. rclpy internals we set or override: Node._default_callback_group, ActionServer._execute_goal.
(_._default_callback_group, _._execute_goal)

# 4. xml.parsers.expat calls the handlers assigned to these attributes (nav_stack/core/bt/xml_model.py).
(_.StartElementHandler, _.EndElementHandler)

# 5. http.server reads these class attributes and calls do_<VERB> and log_message (navsuite_tools/viewer).
(_.daemon_threads, _.allow_reuse_address, _.protocol_version, _.close_connection, _.do_GET, _.do_POST,
 _.log_message)

# 6. pytest calls a collected Item's runtest and reportinfo (navsuite_tools/scenarios/pytest_plugin.py).
(_.runtest, _.reportinfo)

# 7. Python protocols on a metaclass and a module: EventMeta[...] and repr, module __getattr__ (PEP 562).
(_.__getitem__, _.__repr__, _.__getattr__)

# 8. Members of enums and constant sets that mirror an upstream definition, kept complete: looked up by
#    name from a parameter (MotionModel), or the Nav2 error codes and SMACC2 enums they copy.
(_.DiffDrive, _.UNDEFINED_FAILURE, _.FAILED_TO_SMOOTH_PATH, _.LEFT, _.SERVICE3_OFF,
 _.LOCAL_OBSTACLES_LAYER, _.GLOBAL_INFLATED_LAYER, _.LOCAL_INFLATED_LAYER)

# 9. sm_battery_patrol's locations, read by name (SmBatteryPatrolConfig.pose_of, getattr).
(_.location1, _.location2, _.location3, _.location4)

# 10. Nav2 parameters accepted so a Nav2 file loads and never read: each dataclass's IGNORED lists them,
#     nav_stack/ros/common/params.py warns at startup, docs/nav2-differences.md has the table.
(_.save_pose_rate, _.initial_pose_z, _.subscribe_to_updates)

# 11. SMACC2's public API in snake_case, for users' own clients, behaviors and states: kept whether or not a
#     shipped machine calls it (createSiblingComponent, getCurrentState, getStateMachine, getEventGenerator,
#     throwSequenceFinishedEvent, CpPose::toPoseStampedMsg, WaypointNavigator::rewind, ClNav2Z's goal sender).
(_.create_sibling_component, _.get_current_state, _.get_state_machine, _.get_event_generator,
 _.throw_sequence_finished_event, _.to_pose_stamped, _.rewind, _.send_navigation_goal)

# 12. Kept to be read by people and by tests that compare whole records, or to keep an object alive:
#     sim2d's Dropped.silent_for (tests compare Dropped records), test fixtures' references to timers and
#     TF listeners that must live as long as the fixture (_trigger, _timers, _viewer_tf).
(_.silent_for, _._trigger, _._timers, _._viewer_tf)

# 13. SMACC2 parameters accepted and not read (docs/nav2-differences.md says which and why).
(_.clear_angular_distance_threshold,)

# 14. Notes named from docstrings ("see TWIN_NOTE"): text for readers, not code.
(_.TWIN_NOTE,)
