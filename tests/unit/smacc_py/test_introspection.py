"""Static description (smacc2_msgs-shaped) and Mermaid/DOT export, from declarations alone."""

from __future__ import annotations

from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord, describe_state_machine
from smacc_py.core.graph_export import to_dot, to_mermaid
from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1, SmNav2Test1Params
from tests.helpers.smacc_fake_nav import ScriptedNav2
from tests.unit.smacc_py.test_dispatch import EvError, EvGo, EvNext, EvResume, SmHistory


def test_description_mirrors_the_declarations_without_running_anything() -> None:
    desc = describe_state_machine(SmNav2Test1)
    assert desc.initial_state == "StAllSensorsGo"
    assert [s.name for s in desc.states][:2] == ["StAllSensorsGo", "StSetInitialPose"]
    first = desc.state("StAllSensorsGo")
    assert first.level == 0 and first.children_states == ()
    assert [(t.transition_type, t.destiny_state_name) for t in first.transitions] == [
        ("NAV2_READY", "StSetInitialPose"), ("SUCCESS", "StSetInitialPose"), ("NEXT", "StSetInitialPose"),
    ]
    event = first.transitions[0].event
    assert (event.event_type, event.event_source, event.event_object_tag) == (
        "EvCbSuccess", "CbWaitNav2Nodes", "OrNavigation")
    assert {o.name: o.client_behavior_names for o in first.orthogonals} == {
        "OrNavigation": ("CbWaitNav2Nodes",), "OrTimer": ("CbTimerCountdownOnce",),
        "OrKeyboard": ("CbDefaultKeyboardBehavior",),
    }
    indices = [t.index for s in desc.states for t in s.transitions]
    assert indices == list(range(len(indices)))


def test_instance_description_adds_client_names() -> None:
    world = ScriptedNav2()
    sm = SmNav2Test1(now=world.clock, substitutes=world.substitutes(), config=SmNav2Test1Params())
    sm.initialize()  # the stand-in ClNav2Z is described as the client it stands in for
    nav = next(o for o in sm.describe().state("StRotate").orthogonals if o.name == "OrNavigation")
    assert nav.client_names == ("ClNav2Z",) and nav.client_behavior_names == ("CbPureSpinning",)


def test_hierarchy_levels_children_and_history_flags() -> None:
    desc = describe_state_machine(SmHistory)
    assert desc.state("MsRun").children_states == ("StiStep1", "SsStep2")
    assert desc.state("MsRun").inner_initial_state == "StiStep1"
    assert desc.state("StiDeepB").level == 2
    resume = desc.state("MsRecovery").transitions[0]
    assert (resume.history_node, resume.destiny_state_name) == (True, "MsRun")


def test_mermaid_export_shows_superstates_transitions_tags_and_behaviors() -> None:
    text = to_mermaid(SmHistory)
    assert text.startswith("stateDiagram-v2\n    [*] --> StBoot\n")
    assert "    state MsRun {\n        [*] --> StiStep1\n" in text
    assert "        state SsStep2 {\n            [*] --> StiDeepA\n" in text
    assert "    MsRecovery --> MsRun : EvResume / SUCCESS (H*)\n" in text
    nav = to_mermaid(SmNav2Test1)
    assert "StRotate --> StNavigateToWaypoint2 : EvCbSuccess[CbPureSpinning, OrNavigation] / SUCCESS" in nav
    assert "    note right of StRotate\n        OrNavigation: CbPureSpinning\n" in nav


def test_dot_export_uses_clusters_for_superstates() -> None:
    text = to_dot(SmHistory)
    assert text.startswith('digraph "SmHistory" {') and text.rstrip().endswith("}")
    assert 'subgraph "cluster_MsRun" {' in text and 'subgraph "cluster_SsStep2" {' in text
    assert '"MsRecovery" -> "StiStep1" [label="EvResume / SUCCESS (H*)", lhead="cluster_MsRun"];' in text
    assert '__start -> "StBoot";' in text


def test_observer_sees_transitions_in_order_with_tag_and_event() -> None:
    records: list[TransitionRecord] = []

    class Log(SmaccObserver):
        def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
            records.append(record)

    sm = SmHistory()
    sm.add_observer(Log())
    sm.start()
    for event in (EvGo, EvNext, EvError, EvResume):
        sm.post_event(event)
    sm.process_events()
    assert [(r.index, *r.key(), r.leaf.__name__, type(r.event).__name__) for r in records] == [
        (1, "StBoot", "MsRun", "DEFAULT", "StiStep1", "EvGo"),
        (2, "StiStep1", "SsStep2", "DEFAULT", "StiDeepA", "EvNext"),
        (3, "MsRun", "MsRecovery", "ABORT", "MsRecovery", "EvError"),
        (4, "MsRecovery", "MsRun", "SUCCESS", "StiDeepA", "EvResume"),
    ]
    assert records == list(sm.transition_log)


def test_dot_labels_break_lines_with_dot_escapes_not_literal_backslashes():
    from smacc_py.core.graph_export import _quote

    assert _quote("StA\nOrX: CbY") == '"StA\\nOrX: CbY"'
    assert _quote('say "hi" \\ bye') == '"say \\"hi\\" \\\\ bye"'
