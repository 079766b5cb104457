"""The viewer in a real (headless Debian) Chromium while sim2d runs.

``test_viewer_draws_the_running_sim_and_publishes_a_clicked_goal`` runs sim2d (subprocess), fakes
for what the nav stack would add (map_server's /map, AMCL's map → odom at the spawn pose, a global
costmap with one asymmetric lethal block) and a fake SMACC2 machine, then checks from the page's
canvas pixels that the map is drawn +y up, the robot sits where ground truth says, the scan lines up
with the map walls, the state graph highlights the current state, and that a "Nav2 Goal" click-drag
publishes /goal_pose. It asserts the goal *publication* only; whether the robot then arrives is
``test_robot_reaches_a_goal_clicked_in_the_browser``, which runs only when the nav stack's
``nav-bringup`` (nav_stack.ros.bringup.nav_bringup) exists and skips otherwise.

A screenshot is saved to artifacts/ (gitignored). Needs a ``chromium`` on PATH (Debian's package; the
same check scripts/setup.sh makes) and the ``playwright`` package (never ``playwright install``); skips
with the reason when either is missing.
"""

from __future__ import annotations

import contextlib
import importlib.util
import math
import shutil
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from navsuite_testing.ros import REPO, BackgroundSpin, start_python, stop_process, wait_until
from tests.helpers.nav_ros_bt_stack import READY, Bringup

pytestmark = [pytest.mark.slow, pytest.mark.ros]
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--no-first-run", "--disable-sync"]
ARTIFACTS = REPO / "artifacts"
MAP_YAML = REPO / "maps" / "turtlebot3_world.yaml"
SPAWN = (-2.0, -0.5, 0.0)
MARK = (1.6, 0.9)  # the costmap's lethal block: off both symmetry axes of the world
WAIT = 60.0


@pytest.fixture
def browser() -> Iterator[object]:
    chromium_path = shutil.which("chromium")  # what scripts/setup.sh checks (command -v chromium)
    if chromium_path is None:
        pytest.skip("needs Debian's chromium on PATH (apt-get install chromium)")
    if importlib.util.find_spec("playwright") is None:
        pytest.skip("needs the playwright package (pip install playwright; no browser download needed)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=chromium_path, args=CHROMIUM_ARGS, headless=True)
        try:
            yield chromium
        finally:
            chromium.close()


@pytest.fixture
def sim() -> Iterator[object]:
    proc = start_python("sim2d.ros.cli", ["--rtf", "2", "--x", str(SPAWN[0]), "--y", str(SPAWN[1])])
    try:
        yield proc
    finally:
        stop_process(proc)


@pytest.fixture
def viewer(ros_context) -> Iterator[object]:
    from navsuite_tools.viewer.main import ViewerApp
    from navsuite_tools.viewer.params import ViewerParams

    app = ViewerApp(ViewerParams(port=0, discovery_period=0.3), context=ros_context).start()
    try:
        yield app
    finally:
        app.close()


@pytest.fixture
def spinning(ros_context) -> Iterator[object]:
    """Create nodes on the test's context, spun in a background thread."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    executor = SingleThreadedExecutor(context=ros_context)
    nodes = []

    def make_node(name: str) -> object:
        node = rclpy.create_node(name, context=ros_context)
        nodes.append(node)
        executor.add_node(node)
        return node

    spin = BackgroundSpin(executor, "viewer peers")
    try:
        yield make_node
    finally:
        spin.stop(*nodes)


class Page:
    """The loaded page plus a world → canvas-pixel mapping written here, independently of viewer.js."""

    def __init__(self, page: object) -> None:
        self.page = page

    def view(self) -> dict[str, float]:
        return self.page.evaluate("""() => { const c = document.getElementById('map');
            return {...viewer.view, w: c.clientWidth, h: c.clientHeight}; }""")

    def to_screen(self, x: float, y: float) -> tuple[float, float]:
        """CSS pixels of a map point: +x right, +y UP (canvas rows grow downwards)."""
        v = self.view()
        return v["w"] / 2 + (x - v["cx"]) * v["scale"], v["h"] / 2 - (y - v["cy"]) * v["scale"]

    def to_viewport(self, x: float, y: float) -> tuple[float, float]:
        """Page coordinates (what mouse events use) of a map point."""
        sx, sy = self.to_screen(x, y)
        left, top = self.page.evaluate("""() => {
            const r = document.getElementById('map').getBoundingClientRect(); return [r.left, r.top]; }""")
        return left + sx, top + sy

    def pixel(self, x: float, y: float) -> tuple[int, int, int]:
        sx, sy = self.to_screen(x, y)
        return tuple(self.page.evaluate(
            """([sx, sy]) => { const c = document.getElementById('map'), d = window.devicePixelRatio || 1;
                 const px = c.getContext('2d').getImageData(Math.round(sx * d), Math.round(sy * d), 1, 1);
                 return Array.from(px.data.slice(0, 3)); }""", [sx, sy]))


def _start_fakes(node: object) -> object:
    from nav_msgs.msg import OccupancyGrid

    from tests.helpers.viewer_fakes import (
        LATCHED,
        FakeSmacc,
        map_from_file,
        map_to_odom,
        marker_costmap,
        publish_static,
    )

    node.create_publisher(OccupancyGrid, "/map", LATCHED).publish(map_from_file(str(MAP_YAML)))
    node.create_publisher(OccupancyGrid, "/global_costmap/costmap", LATCHED).publish(
        marker_costmap(6.0, 0.05, MARK))
    node._viewer_tf = publish_static(node, [map_to_odom(*SPAWN)])  # keep the broadcaster alive
    smacc = FakeSmacc(node)
    node.create_timer(0.5, smacc.publish)
    return smacc


def _occupied_points(yaml_path: Path) -> np.ndarray:
    from nav_stack.core.map_io import load_map

    m = load_map(yaml_path)
    rows, cols = np.nonzero(m.data >= 65)
    s = m.spec
    return np.column_stack((s.origin_x + (cols + 0.5) * s.resolution,
                            s.origin_y + (rows + 0.5) * s.resolution))


def test_viewer_draws_the_running_sim_and_publishes_a_clicked_goal(browser, sim, viewer, spinning):
    from geometry_msgs.msg import PoseStamped

    node = spinning("viewer_browser_fakes")
    smacc = _start_fakes(node)
    goals: list[PoseStamped] = []
    node.create_subscription(PoseStamped, "/goal_pose", goals.append, 10)

    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto(viewer.url)
    page.wait_for_function(
        """() => viewer.drawn.map && viewer.drawn.global_costmap && viewer.drawn.truth
                 && viewer.drawn.scan > 30 && document.querySelector('#machines .node.current')""",
        timeout=WAIT * 1000)
    view = Page(page)

    # the robot is drawn where ground truth puts it, and ground truth is the spawn pose (the robot is idle)
    truth = page.evaluate("() => viewer.layers.truth.pose")
    assert truth[:2] == pytest.approx(SPAWN[:2], abs=0.05)
    r, g, b = view.pixel(truth[0], truth[1])
    assert g > r + 30 and g > b + 30, ("robot fill (green) at the ground-truth pose", (r, g, b))
    # grids are drawn +y up and not mirrored: the lethal block shows only at MARK
    r, g, b = view.pixel(*MARK)
    assert r > 150 and b > 150 and g < 100, ("lethal (magenta) costmap cells at", MARK, (r, g, b))
    for x, y in ((MARK[0], -MARK[1]), (-MARK[0], MARK[1])):
        r, g, b = view.pixel(x, y)
        assert not (r > 150 and b > 150 and g < 100), ("mirrored costmap block at", (x, y))
    # the map: a pillar of the TurtleBot3 world is dark, the free space beside it is light
    assert max(view.pixel(1.1, 1.1)) < 90
    assert min(view.pixel(0.55, 0.55)) > 180
    # the scan (base_scan → odom → map through TF) lands on the map's obstacles
    points = np.array(page.evaluate("() => viewer.layers.scan.points")).reshape(-1, 2)
    walls = _occupied_points(MAP_YAML)
    nearest = np.min(np.linalg.norm(points[:, None, :] - walls[None, :, :], axis=2), axis=1)
    assert np.mean(nearest < 0.1) > 0.9, np.percentile(nearest, [50, 90])

    # the state graph: four states, the current one highlighted; it follows a transition
    assert page.eval_on_selector_all("#machines .node", "ns => ns.length") == 4
    assert page.get_attribute("#machines .node.current", "data-state") == "StAcquireSensors"
    smacc.transition("StNavigate", "SUCCESS", "EvCbSuccess")
    page.wait_for_function("() => document.querySelector('#machines .node.current')?.dataset.state"
                           " === 'StNavigate' && document.querySelector('#machines .edge.recent')",
                           timeout=WAIT * 1000)

    # "Nav2 Goal": click at a map point and drag towards +x → /goal_pose at that point, yaw 0
    target = (0.5, -1.0)
    page.click("button[data-tool=goal]")
    drag(page, *view.to_viewport(*target))
    wait_until(lambda: goals, WAIT, "/goal_pose from the browser click")
    pixel = 1.0 / view.view()["scale"]
    goal = goals[-1]
    assert goal.header.frame_id == "map"
    assert (goal.pose.position.x, goal.pose.position.y) == pytest.approx(target, abs=2 * pixel)
    assert 2 * math.atan2(goal.pose.orientation.z, goal.pose.orientation.w) == pytest.approx(0.0, abs=0.05)
    page.wait_for_function("() => viewer.drawn.goal", timeout=WAIT * 1000)  # echoed back on the map

    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / "viewer_browser.png"))


@pytest.mark.skipif(importlib.util.find_spec("nav_stack.ros.bringup.nav_bringup") is None,
                    reason="needs the nav stack (nav_stack.ros.bringup.nav_bringup / nav-bringup) "
                           "for the arrival check")
def drag(page: object, sx: float, sy: float) -> None:
    """Press at (sx, sy) viewport px and drag 60 px to the right (a pose facing +x)."""
    page.mouse.move(sx, sy)
    page.mouse.down()
    page.mouse.move(sx + 60, sy, steps=4)
    page.mouse.up()


def test_robot_reaches_a_goal_clicked_in_the_browser(browser, viewer):
    """Whole stack: pose estimate and goal clicked in the page; the simulated robot arrives.

    nav-bringup starts its own simulator (no ``sim`` fixture: two simulators would publish two
    clocks and two robots' TF) and no initial pose, which the page's "2D Pose Estimate" gives.

    The clicks wait for "Nav2 is ready", as a user does: bt_navigator rejects a goal while it is not
    active yet, as Nav2's does (CI run CQ: the goal was clicked while the loaded machine was still
    bringing the stack up, and the robot never moved)."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    stack = Bringup("--no-initial-pose")
    try:
        stack.wait_for_line(READY, timeout=240.0)
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.goto(viewer.url)
        page.wait_for_function("() => viewer.drawn.map && viewer.drawn.truth", timeout=WAIT * 2000)
        view = Page(page)
        for tool, (x, y) in (("initial_pose", SPAWN[:2]), ("goal", (0.5, -1.6))):
            page.wait_for_function("() => viewer.tool === 'pan'")
            page.click(f"button[data-tool={tool}]")
            sx, sy = view.to_viewport(x, y)
            drag(page, sx, sy)
            if tool == "initial_pose":
                # AMCL may not have matched the viewer's /initialpose publisher yet (DDS discovery,
                # wall seconds under load): set the pose again until AMCL answers, as a user would.
                for _ in range(3):
                    with contextlib.suppress(PlaywrightTimeout):
                        page.wait_for_function("() => viewer.drawn.amcl", timeout=20_000)
                        break
                    page.click(f"button[data-tool={tool}]")
                    drag(page, sx, sy)
                page.wait_for_function("() => viewer.drawn.amcl", timeout=WAIT * 1000)

        def near_goal() -> bool:
            pose = page.evaluate("() => viewer.layers.truth.pose")
            return math.hypot(pose[0] - 0.5, pose[1] + 1.6) < 0.3

        wait_until(near_goal, 180.0, "the robot at the clicked goal", step=0.5)
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "viewer_browser_arrival.png"))
    finally:
        stack.stop()
