"""Computation graph (handout Ex. 15): the live nodes, topics and message types, drawn left to right.

Why not rqt_graph: it needs a desktop, Qt and the ROS GUI stack, none of which a laptop in
preparation or a notebook has. The master already knows everything Ex. 15 asks for:
``getSystemState`` (who publishes and subscribes what) and ``getTopicTypes`` -- two XML-RPC
calls, no rospy (:func:`read_graph`). The drawing is a plain layered layout
(:func:`layered_layout`): data flows left to right from the sensor to the robot, nodes
and topics alternate, each layer ordered to keep edges short.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Set, Tuple

import ipywidgets as widgets
from matplotlib.figure import Figure

from hri_teleop.course.notebook_ros import current_session
from hri_teleop.course.widgets._base import FigureView, message_html
from hri_teleop.ros.master_api import MasterApiError, master_call, master_uri

__all__ = ["RosGraph", "ROS_INTERNAL_TOPICS", "ROS_INTERNAL_NODES", "graph_from_state", "layered_layout",
           "wrap_name", "draw_graph", "read_graph", "GraphView"]

#: What every ROS system has and Ex. 15's flowchart leaves out (shown with show_ros_internals).
ROS_INTERNAL_TOPICS = ("/rosout", "/rosout_agg")
ROS_INTERNAL_NODES = ("/rosout",)

Key = Tuple[str, str]  # ("node", name) or ("topic", name): a node and a topic may share a name


@dataclass(frozen=True)
class RosGraph:
    """Nodes, topics with their types, and who publishes / subscribes what (sorted, deduplicated)."""

    nodes: Tuple[str, ...]
    topics: Mapping[str, str]  # topic -> message type ("" if the master does not know it)
    publishes: Tuple[Tuple[str, str], ...]  # (node, topic)
    subscribes: Tuple[Tuple[str, str], ...]  # (node, topic)


def graph_from_state(system_state: Sequence[Any], topic_types: Iterable[Sequence[str]], *,
                     hide_nodes: Iterable[str] = (), show_ros_internals: bool = False) -> RosGraph:
    """The graph from the master's ``getSystemState`` value ([pubs, subs, srvs]) and ``getTopicTypes``.

    Nodes that only offer services (every rospy node does) are kept, so a node that
    publishes nothing still shows; ``hide_nodes`` (e.g. the notebook's own node) and,
    unless ``show_ros_internals``, /rosout are left out.
    """
    pubs, subs = system_state[0], system_state[1]
    srvs = system_state[2] if len(system_state) > 2 else []
    hidden_nodes: Set[str] = set(hide_nodes)
    hidden_topics: Set[str] = set()
    if not show_ros_internals:
        hidden_nodes |= set(ROS_INTERNAL_NODES)
        hidden_topics |= set(ROS_INTERNAL_TOPICS)
    types = {str(t): str(k) for t, k in topic_types}
    nodes: Set[str] = set()
    topics: Dict[str, str] = {}
    edges: Dict[str, Set[Tuple[str, str]]] = {"pub": set(), "sub": set()}
    for kind, entries in (("pub", pubs), ("sub", subs)):
        for topic, names in entries:
            if topic in hidden_topics:
                continue
            for node in names:
                if node in hidden_nodes:
                    continue
                topics[topic] = types.get(topic, "")
                nodes.add(node)
                edges[kind].add((node, topic))
    for _service, names in srvs:
        nodes.update(n for n in names if n not in hidden_nodes)
    return RosGraph(tuple(sorted(nodes)), dict(sorted(topics.items())), tuple(sorted(edges["pub"])),
                    tuple(sorted(edges["sub"])))


def _successors(graph: RosGraph) -> Dict[Key, List[Key]]:
    succ: Dict[Key, List[Key]] = {("node", n): [] for n in graph.nodes}
    succ.update({("topic", t): [] for t in graph.topics})
    for node, topic in graph.publishes:
        succ[("node", node)].append(("topic", topic))
    for node, topic in graph.subscribes:
        succ[("topic", topic)].append(("node", node))
    return succ


def layered_layout(graph: RosGraph) -> Dict[Key, Tuple[float, float]]:
    """(x, y) per ("node", name) / ("topic", name): x = layer (data flows to +x), y centred per layer.

    Cycles (a node that subscribes to what it publishes, feedback loops) are broken at
    the edge that a depth-first search from the sources meets last; each vertex then sits
    one layer right of its furthest predecessor, and a layer is ordered by the mean
    position of its predecessors (one barycentre sweep), ties by name.
    """
    succ = _successors(graph)
    indegree = {key: 0 for key in succ}
    for targets in succ.values():
        for target in targets:
            indegree[target] += 1
    roots = sorted(k for k in succ if indegree[k] == 0) + sorted(k for k in succ if indegree[k] > 0)
    back: Set[Tuple[Key, Key]] = set()
    state: Dict[Key, int] = {}  # 1 on the DFS stack, 2 finished
    for root in roots:
        if root in state:
            continue
        stack = [(root, iter(sorted(succ[root])))]
        state[root] = 1
        while stack:
            vertex, children = stack[-1]
            child = next(children, None)
            if child is None:
                state[vertex] = 2
                stack.pop()
            elif state.get(child) == 1:
                back.add((vertex, child))
            elif child not in state:
                state[child] = 1
                stack.append((child, iter(sorted(succ[child]))))
    dag = {k: [t for t in v if (k, t) not in back] for k, v in succ.items()}
    preds: Dict[Key, List[Key]] = {k: [] for k in succ}
    for source, targets in dag.items():
        for target in targets:
            preds[target].append(source)
    rank: Dict[Key, int] = {}
    remaining = {k: len(v) for k, v in preds.items()}
    ready = sorted(k for k, n in remaining.items() if n == 0)
    while ready:
        vertex = ready.pop(0)
        rank[vertex] = max((rank[p] + 1 for p in preds[vertex]), default=0)
        for target in dag[vertex]:
            remaining[target] -= 1
            if remaining[target] == 0:
                ready.append(target)
        ready.sort()
    layers: Dict[int, List[Key]] = {}
    for key in sorted(rank, key=lambda k: (rank[k], k)):
        layers.setdefault(rank[key], []).append(key)
    position: Dict[Key, Tuple[float, float]] = {}
    for layer in sorted(layers):
        members = layers[layer]

        def barycentre(key: Key) -> float:
            ys = [position[p][1] for p in preds[key] if p in position]
            return -sum(ys) / len(ys) if ys else 0.0

        members.sort(key=lambda k: (barycentre(k), k))
        middle = (len(members) - 1) / 2.0
        for index, key in enumerate(members):
            position[key] = (float(layer), middle - index)
    return position


def wrap_name(name: str, width: int = 22) -> str:
    """A ROS name broken before '/' so that no line is much longer than ``width`` characters."""
    lines: List[str] = []
    for part in name.replace("/", "\n/").split("\n"):
        if not part:
            continue
        if lines and len(lines[-1]) + len(part) <= width:
            lines[-1] += part
        else:
            lines.append(part)
    return "\n".join(lines) or name


def draw_graph(graph: RosGraph, figure: Optional[Figure] = None, title: str = "") -> Figure:
    """The graph as a matplotlib Figure: nodes as rounded blue boxes, topics as yellow boxes with their type."""
    position = layered_layout(graph)
    layers = max((int(x) for x, _ in position.values()), default=0) + 1
    tallest = max((sum(1 for x, _ in position.values() if int(x) == layer) for layer in range(layers)), default=1)
    if figure is None:
        figure = Figure(figsize=(max(6.0, 2.4 * layers), max(2.6, 0.95 * tallest + 1.0)), dpi=80)
    figure.clear()
    ax = figure.add_axes((0.0, 0.0, 1.0, 0.92 if title else 1.0))
    ax.set_axis_off()
    if not position:
        ax.text(0.5, 0.5, "no nodes: start the lab's launch file, then refresh", ha="center", va="center")
        return figure
    artists: Dict[Key, Any] = {}
    for key, (x, y) in position.items():
        kind, name = key
        if kind == "node":
            artists[key] = ax.text(x, y, wrap_name(name), ha="center", va="center", fontsize=9, zorder=3,
                                   bbox=dict(boxstyle="round,pad=0.5", fc="#cfe2ff", ec="#1f4e9c"))
        else:
            kind_text = graph.topics.get(name) or "type unknown"
            artists[key] = ax.text(x, y, wrap_name(name) + "\n[" + kind_text + "]", ha="center", va="center",
                                   fontsize=8, zorder=3, bbox=dict(boxstyle="square,pad=0.35", fc="#fff3c4",
                                                                   ec="#a07800"))
    edges = [(("node", n), ("topic", t)) for n, t in graph.publishes]
    edges += [(("topic", t), ("node", n)) for n, t in graph.subscribes]
    for source, target in edges:
        forward = position[target][0] > position[source][0]
        ax.annotate("", xy=(0.0, 0.5) if forward else (0.5, 0.0), xycoords=artists[target],
                    xytext=(1.0, 0.5) if forward else (0.5, 0.0), textcoords=artists[source],
                    arrowprops=dict(arrowstyle="-|>", color="0.35", lw=1.0, shrinkA=1, shrinkB=1,
                                    connectionstyle="arc3,rad=0.0" if forward else "arc3,rad=0.4"), zorder=2)
    xs = [x for x, _ in position.values()]
    ys = [y for _, y in position.values()]
    ax.set_xlim(min(xs) - 0.6, max(xs) + 0.6)
    ax.set_ylim(min(ys) - 0.7, max(ys) + 0.7)
    if title:
        figure.suptitle(title, fontsize=10)
    return figure


def read_graph(uri: Optional[str] = None, *, hide_nodes: Optional[Iterable[str]] = None,
               show_ros_internals: bool = False, timeout_s: float = 2.0) -> RosGraph:
    """The live graph from the master at ``uri`` (default: this kernel's ``ROS_MASTER_URI``).

    ``hide_nodes`` defaults to this kernel's own node (:func:`~hri_teleop.course.notebook_ros.ensure_ros`),
    which is an observer, not part of the pipeline. MasterApiError if no master answers.
    """
    if hide_nodes is None:
        session = current_session()
        hide_nodes = [session.node_name] if session is not None and session.node_name else []
    state = master_call("getSystemState", uri=uri, timeout_s=timeout_s)
    types = master_call("getTopicTypes", uri=uri, timeout_s=timeout_s)
    return graph_from_state(state, types, hide_nodes=hide_nodes, show_ros_internals=show_ros_internals)


class GraphView(widgets.VBox):
    """The live graph with a refresh button (and /rosout on request). ``view.graph`` is the last one read."""

    def __init__(self, uri: Optional[str] = None, *, show_ros_internals: bool = False, figure: str = "auto") -> None:
        self.uri = uri
        self.figure_mode = figure
        self.graph: Optional[RosGraph] = None
        self.refresh_button = widgets.Button(description="refresh", icon="refresh")
        self.internals = widgets.Checkbox(value=show_ros_internals, description="show /rosout", indent=False)
        self.status = widgets.HTML()
        self.view: Optional[FigureView] = None
        self._holder = widgets.Box()
        self.refresh_button.on_click(lambda _b: self.refresh())
        self.internals.observe(lambda _c: self.refresh(), names="value")
        super().__init__([widgets.HBox([self.refresh_button, self.internals]), self.status, self._holder])
        self.refresh()

    def refresh(self) -> Optional[RosGraph]:
        """Read the graph again and draw it; a missing master becomes one line in the widget."""
        uri = self.uri or master_uri()
        try:
            graph = read_graph(uri, show_ros_internals=self.internals.value)
        except MasterApiError as exc:
            self.status.value = message_html(str(exc), error=True)
            return None
        self.graph = graph
        if self.view is not None:
            self.view.widget.close()  # one canvas per refresh: release the old one's comm
        self.view = FigureView(draw_graph(graph, title=f"ROS graph at {uri}"), self.figure_mode)
        self._holder.children = (self.view.widget,)
        self.status.value = message_html(f"{len(graph.nodes)} nodes, {len(graph.topics)} topics "
                                         f"({len(graph.publishes)} publications, {len(graph.subscribes)} "
                                         "subscriptions)")
        return graph
