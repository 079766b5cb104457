"""Folding event streams into viewable state: SMACC2 state machines and Nav2 behavior trees.

Unlike map-like layers these topics carry *events* (a transition, a batch of BT status changes):
dropping one would leave the page wrong, so every message is folded here into a bounded state
(latest status per node, the last N transitions) and the page receives snapshots of that state.
No ROS types: the node translates messages into the small records below.

State names: SMACC2 describes states by their full C++ names (``sm_x::StNavigate``) while
``SmaccStatus.current_states`` may hold short ones, so names are matched by their last component.
"""

from __future__ import annotations

import json
import threading
from collections import deque
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass

#: How many past transitions / BT status changes a snapshot carries.
HISTORY = 30


def short_name(name: str) -> str:
    """``ns::sub::StFoo`` or ``pkg.mod.StFoo`` → ``StFoo`` (template arguments kept)."""
    head = name.split("<", 1)
    base = head[0].replace(".", "::").rsplit("::", 1)[-1]
    return base + ("<" + head[1] if len(head) > 1 else "")


# ---------------------------------------------------------------- state machines
@dataclass(frozen=True)
class TransitionInfo:
    """One SmaccTransition: ``tag`` is SMACC2's transition_type (SUCCESS, ABORT, ...)."""

    source: str
    target: str
    tag: str
    name: str = ""
    event: str = ""


@dataclass(frozen=True)
class StateInfo:
    """One SmaccState of a description; ``children`` are the names of nested states."""

    name: str
    level: int
    children: tuple[str, ...]
    transitions: tuple[TransitionInfo, ...]
    orthogonals: tuple[tuple[str, tuple[str, ...]], ...] = ()  # (orthogonal, client behaviours)


def layered_layout(nodes: Sequence[str], edges: Iterable[tuple[str, str]]) -> dict[str, tuple[int, int]]:
    """Place nodes in layers for a top-down drawing: ``{node: (layer, order within layer)}``.

    Layer = breadth-first depth from the first node (the initial state) along ``edges``; nodes it
    does not reach start new searches in list order, below what is placed. Within a layer nodes are
    ordered by the mean order of their already placed predecessors (one barycentre pass), which
    removes most crossings of the mostly linear graphs state machines have.
    """
    succ: dict[str, list[str]] = {n: [] for n in nodes}
    pred: dict[str, list[str]] = {n: [] for n in nodes}
    for a, b in edges:
        if a in succ and b in succ and a != b:
            succ[a].append(b)
            pred[b].append(a)
    layer: dict[str, int] = {}
    base = 0
    for root in nodes:
        if root in layer:
            continue
        layer[root] = base
        frontier = [root]
        while frontier:
            nxt = []
            for n in frontier:
                for m in succ[n]:
                    if m not in layer:
                        layer[m] = layer[n] + 1
                        nxt.append(m)
            frontier = nxt
        base = max(layer.values()) + 1
    order: dict[str, int] = {}
    by_layer: dict[int, list[str]] = {}
    for n in nodes:  # list order breaks ties
        by_layer.setdefault(layer[n], []).append(n)
    for depth in sorted(by_layer):
        members = by_layer[depth]

        def barycentre(n: str, members: list[str] = members) -> float:
            placed = [order[p] for p in pred[n] if p in order]
            return sum(placed) / len(placed) if placed else float(members.index(n))

        for i, n in enumerate(sorted(members, key=barycentre)):
            order[n] = i
    return {n: (layer[n], order[n]) for n in nodes}


class SmaccMonitor:
    """What one SMACC2 state machine looks like now: its graph, current states and recent transitions."""

    def __init__(self, name: str, history: int = HISTORY) -> None:
        self.name = name
        self.revision = 0  # bumps on every visible change: the hub's digest for this layer
        self._lock = threading.Lock()
        self._states: tuple[StateInfo, ...] = ()
        self._current: tuple[str, ...] = ()
        self._variables: dict[str, str] = {}
        self._log: deque[dict[str, object]] = deque(maxlen=history)

    def set_description(self, states: Sequence[StateInfo]) -> None:
        with self._lock:
            if tuple(states) != self._states:
                self._states = tuple(states)
                self.revision += 1

    def set_status(self, current_states: Sequence[str], variables: dict[str, str]) -> None:
        current = tuple(short_name(s) for s in current_states)
        with self._lock:
            if current != self._current or variables != self._variables:
                self._current, self._variables = current, dict(variables)
                self.revision += 1

    def add_transition(self, stamp: float, transition: TransitionInfo) -> None:
        entry = {"stamp": stamp, **asdict(transition)}
        entry["source"], entry["target"] = short_name(transition.source), short_name(transition.target)
        with self._lock:
            self._log.append(entry)
            self.revision += 1

    def snapshot(self) -> dict[str, object]:
        """The JSON-ready view of the machine (nodes placed by :func:`layered_layout`)."""
        with self._lock:
            states, current, variables, log = self._states, self._current, self._variables, list(self._log)
        names = [short_name(s.name) for s in states]
        edges = []
        for s in states:
            for t in s.transitions:
                edges.append({"source": short_name(t.source or s.name), "target": short_name(t.target),
                              "tag": t.tag, "event": short_name(t.event) if t.event else "",
                              "kind": "transition"})
            for child in s.children[:1]:  # a superstate enters its first child: draw it as a dashed edge
                edges.append({"source": short_name(s.name), "target": short_name(child), "tag": "",
                              "event": "", "kind": "child"})
        for e in edges:  # transitions may name states the description does not list (terminal states)
            for end in (e["source"], e["target"]):
                if end not in names:
                    names.append(end)
        place = layered_layout(names, [(e["source"], e["target"]) for e in edges])
        info = {short_name(s.name): s for s in states}
        nodes = []
        for n in names:
            state = info.get(n)
            nodes.append({
                "id": n, "layer": place[n][0], "order": place[n][1], "level": state.level if state else 0,
                "orthogonals": [[o, list(b)] for o, b in state.orthogonals] if state else [],
            })
        return {"name": self.name, "nodes": nodes, "edges": edges, "current": list(current),
                "variables": variables, "transitions": log}


# ---------------------------------------------------------------- behavior trees
@dataclass(frozen=True)
class BtEvent:
    """One nav2_msgs/BehaviorTreeStatusChange (stamp in s)."""

    stamp: float
    name: str
    uid: int
    previous: str
    current: str


class BtMonitor:
    """Per-node last status of a running behavior tree plus the recent status changes.

    Nav2's bt_navigator publishes only changes (``/behavior_tree_log``); BT.CPP numbers nodes in
    depth-first order, so sorting by uid lists them in tree order. If a structure is published
    (``std_msgs/String`` JSON: ``{"name", "uid"?, "type"?, "children": [...]}``) the page draws it
    as a tree and colours each node by the status recorded for its uid (or name).
    """

    def __init__(self, history: int = HISTORY) -> None:
        self._lock = threading.Lock()
        self._nodes: dict[int, dict[str, object]] = {}
        self._recent: deque[dict[str, object]] = deque(maxlen=history)
        self._structure: object = None
        self._batches = 0

    def apply(self, events: Iterable[BtEvent]) -> None:
        with self._lock:
            self._batches += 1
            for e in events:
                node = self._nodes.setdefault(e.uid, {"uid": e.uid, "name": e.name, "changes": 0})
                node.update(name=e.name, status=e.current, previous=e.previous, stamp=e.stamp)
                node["changes"] = int(node["changes"]) + 1  # type: ignore[call-overload]
                self._recent.append(asdict(e))

    def set_structure(self, text: str) -> None:
        """Accept a tree structure as JSON text; ValueError naming the problem if it is not one."""
        try:
            tree = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"behavior tree structure is not JSON: {exc}") from exc
        _check_tree(tree, "tree")
        with self._lock:
            self._structure = tree

    def snapshot(self) -> dict[str, object]:
        with self._lock:
            return {"nodes": [dict(self._nodes[k]) for k in sorted(self._nodes)],
                    "recent": list(self._recent), "structure": self._structure, "batches": self._batches}


def _check_tree(node: object, path: str) -> None:
    if not isinstance(node, dict) or not isinstance(node.get("name"), str):
        raise ValueError(f"behavior tree structure: {path} must be an object with a string 'name'")
    children = node.get("children", [])
    if not isinstance(children, list):
        raise ValueError(f"behavior tree structure: {path}.children must be a list")
    for i, child in enumerate(children):
        _check_tree(child, f"{path}.children[{i}]")
