"""Mermaid and Graphviz DOT text of a machine, from its declarations alone.

Both show superstates as nested boxes with their initial state, every transition labelled with its
event and tag (``H*`` marks a deep-history target), and a note per state listing the behaviors it runs
on each orthogonal plus its reactors and generators, which SMACC2's closed viewer shows and YASMIN's
outcome-only Mermaid view cannot.
"""

from __future__ import annotations

from smacc_py.core.introspection import StateDescription, StateMachineDescription, describe_state_machine


def _edge_label(event_label: str, tag: str, history: bool) -> str:
    text = f"{event_label} / {tag}"
    return f"{text} (H*)" if history else text


def _parts(state: StateDescription) -> list[str]:
    lines = [f"{o.name}: {', '.join(o.client_behavior_names)}" for o in state.orthogonals]
    lines += [f"reactor {r.type_name}" for r in state.state_reactors]
    lines += [f"generator {g.type_name}" for g in state.event_generators]
    return lines


def to_mermaid(sm: type | StateMachineDescription) -> str:
    """A ``stateDiagram-v2`` diagram."""
    desc = sm if isinstance(sm, StateMachineDescription) else describe_state_machine(sm)
    by_name = {s.name: s for s in desc.states}
    lines = ["stateDiagram-v2", f"    [*] --> {desc.initial_state}"]

    def emit(state: StateDescription, indent: str) -> None:
        if state.children_states:
            lines.append(f"{indent}state {state.name} {{")
            lines.append(f"{indent}    [*] --> {state.inner_initial_state}")
            for child in state.children_states:
                emit(by_name[child], indent + "    ")
            lines.append(f"{indent}}}")
        else:
            lines.append(f"{indent}state {state.name}")

    for state in desc.states:
        if state.level == 0:
            emit(state, "    ")
    for state in desc.states:
        for tr in state.transitions:
            label = _edge_label(tr.event.label, tr.transition_type, tr.history_node)
            lines.append(f"    {tr.source_state_name} --> {tr.destiny_state_name} : {label}")
    for state in desc.states:
        parts = _parts(state)
        if parts:
            lines.append(f"    note right of {state.name}")
            lines.extend(f"        {p}" for p in parts)
            lines.append("    end note")
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    """A dot string literal; real newlines become dot's line-break escape."""
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    return '"' + escaped.replace("\n", "\\n") + '"'


def to_dot(sm: type | StateMachineDescription) -> str:
    """A Graphviz ``digraph``; superstates are clusters, edges to or from them use lhead/ltail."""
    desc = sm if isinstance(sm, StateMachineDescription) else describe_state_machine(sm)
    by_name = {s.name: s for s in desc.states}
    lines = [f"digraph {_quote(desc.name)} {{", "    compound=true;", "    node [shape=box, style=rounded];",
             '    __start [shape=point, label=""];']

    def anchor(name: str) -> str:
        state = by_name[name]
        while state.children_states:
            state = by_name[state.inner_initial_state]
        return state.name

    def emit(state: StateDescription, indent: str) -> None:
        parts = _parts(state)
        label = "\n".join([state.name, *parts])
        if state.children_states:
            lines.append(f"{indent}subgraph {_quote('cluster_' + state.name)} {{")
            lines.append(f"{indent}    label={_quote(label)};")
            for child in state.children_states:
                emit(by_name[child], indent + "    ")
            lines.append(f"{indent}}}")
        else:
            lines.append(f"{indent}{_quote(state.name)} [label={_quote(label)}];")

    for state in desc.states:
        if state.level == 0:
            emit(state, "    ")
    lines.append(f"    __start -> {_quote(anchor(desc.initial_state))};")
    for state in desc.states:
        for tr in state.transitions:
            attrs = [f"label={_quote(_edge_label(tr.event.label, tr.transition_type, tr.history_node))}"]
            if by_name[tr.source_state_name].children_states:
                attrs.append(f"ltail={_quote('cluster_' + tr.source_state_name)}")
            if by_name[tr.destiny_state_name].children_states:
                attrs.append(f"lhead={_quote('cluster_' + tr.destiny_state_name)}")
            src, dst = anchor(tr.source_state_name), anchor(tr.destiny_state_name)
            lines.append(f"    {_quote(src)} -> {_quote(dst)} [{', '.join(attrs)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"
