"""Event classes: identity of parameterisations, payloads, default tags, generated families."""

from __future__ import annotations

import pytest

from smacc_py.core import (
    ABORT,
    CANCEL,
    CONTINUELOOP,
    DEFAULT,
    SUCCESS,
    EvActionAborted,
    EvActionCancelled,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvKeyPress,
    EvLoopContinue,
    EvTopicMessage,
    EvWaypoint,
    SmaccEvent,
    key_press_event,
    waypoint_event,
)
from smacc_py.core import events as events_module


class ClA:
    pass


class OrB:
    pass


class EvMaxRetriesExceeded(SmaccEvent):
    pass


def test_same_parameters_give_the_same_class_object() -> None:
    first = EvCbSuccess[ClA, OrB]
    assert first is EvCbSuccess[ClA, OrB]
    assert first is not EvCbSuccess[OrB, ClA] and first is not EvCbFailure[ClA, OrB]
    assert {first: 1}[EvCbSuccess[ClA, OrB]] == 1
    assert issubclass(first, EvCbSuccess) and first.template is EvCbSuccess
    assert (first.source, first.orthogonal, first.params) == (ClA, OrB, (ClA, OrB))
    assert repr(first) == "EvCbSuccess[ClA, OrB]" == first.get_event_label()


def test_user_events_are_parameterised_the_same_way() -> None:
    event_type = EvMaxRetriesExceeded[ClA, OrB]
    assert event_type is EvMaxRetriesExceeded[ClA, OrB] and event_type.template is EvMaxRetriesExceeded
    assert event_type.get_default_transition_tag() is DEFAULT


def test_payload_is_carried_as_attributes_and_may_not_shadow_parameters() -> None:
    event = EvTopicMessage[ClA, OrB](msg={"ranges": [1.0]})
    assert event.msg == {"ranges": [1.0]} and event.source is ClA
    with pytest.raises(TypeError, match="payload field 'source' shadows"):
        EvTopicMessage[ClA, OrB](source=3)


def test_wrong_arity_and_double_parameterisation_are_rejected() -> None:
    with pytest.raises(TypeError, match=r"EvCbSuccess takes 2 parameters \('source', 'orthogonal'\), got 1"):
        EvCbSuccess[ClA]
    with pytest.raises(TypeError, match="already parameterised"):
        EvCbSuccess[ClA, OrB][ClA, OrB]
    with pytest.raises(TypeError, match="must be hashable"):
        EvCbSuccess[ClA, []]
    assert EvLoopContinue[ClA].state is ClA


@pytest.mark.parametrize(
    ("template", "tag"),
    [(EvActionSucceeded, SUCCESS), (EvActionAborted, ABORT), (EvActionCancelled, CANCEL),
     (EvCbSuccess, SUCCESS), (EvCbFailure, ABORT), (EvLoopContinue, CONTINUELOOP)],
)
def test_default_transition_tag_is_derived_from_the_event(template: type[SmaccEvent], tag: type) -> None:
    assert template[ClA, OrB].get_default_transition_tag() is tag if len(template.param_names) == 2 else True
    assert template.get_default_transition_tag() is tag


def test_key_press_and_waypoint_families() -> None:
    assert events_module.EvKeyPressN is key_press_event("n") and issubclass(key_press_event("Z"), EvKeyPress)
    assert events_module.EvKeyPressN.key == "N"
    assert events_module.EvWaypoint44 is waypoint_event(44) and waypoint_event(0).index == 0
    assert issubclass(waypoint_event(3), EvWaypoint)
    with pytest.raises(ValueError, match="only letters"):
        key_press_event("1")
    with pytest.raises(ValueError, match=r"outside 0\.\.44"):
        waypoint_event(45)
    with pytest.raises(AttributeError):
        events_module.EvKeyPressAA  # noqa: B018


def test_custom_tags_keep_their_family() -> None:
    class NAV2_READY(SUCCESS):
        pass

    assert NAV2_READY.tag_name() == "NAV2_READY" and NAV2_READY.family() == "SUCCESS"
    with pytest.raises(TypeError, match="transition tag class"):
        SUCCESS()
