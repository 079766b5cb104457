"""The README and docs/ stay true: every command they name exists, starts, and is exercised by a test.

`make test` and `make demo` are run by CI and by the demo's system test; the console commands in the
README and in every page of docs/ are registered entry points, and every registered command (shown or
not) is checked here: its function imports, answers ``--help`` with exit status 0, and is run by at
least one other test file (by its command name or its module). The README stays a front door (at
most 220 lines) that links every docs/ page, and every relative link in them leads to a file that
exists.
"""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
_TABLE = (REPO / "pyproject.toml").read_text().split("[project.scripts]", 1)[1].split("\n[", 1)[0]
SCRIPTS: dict[str, str] = dict(re.findall(r'^([\w-]+) = "([\w.]+:\w+)"', _TABLE, re.MULTILINE))
README = (REPO / "README.md").read_text(encoding="utf-8")
DOCS = sorted((REPO / "docs").glob("*.md"))
PAGES = {path: path.read_text(encoding="utf-8") for path in [REPO / "README.md", *DOCS]}

pytestmark = pytest.mark.ros


def shown_commands(text: str) -> set[str]:
    """Registered console commands that start a line of a code block or an inline code span."""
    blocks = re.findall(r"```[a-z]*\n(.*?)```", text, re.DOTALL)
    prose = re.sub(r"```.*?```", "", text, flags=re.DOTALL)
    candidates = [line for block in blocks for line in block.splitlines()] + re.findall(r"`([^`]+)`", prose)
    firsts = {candidate.split()[0] for candidate in candidates if candidate.split()}
    return {first for first in firsts if first in SCRIPTS}


def readme_commands() -> list[str]:
    """The commands the README and the docs/ pages show."""
    return sorted(set().union(*(shown_commands(text) for text in PAGES.values())))


def test_the_readme_names_the_main_commands():
    named = shown_commands(README)
    for command in ("navsuite-demo", "nav-bringup", "nav-goal", "sim2d", "smacc-run", "ros2py",
                    "navsuite-scenarios", "navsuite-viewer"):
        assert command in named


def test_the_readme_is_short_and_links_every_docs_page():
    assert len(README.splitlines()) <= 220, "the README is a front door: move the depth to docs/"
    linked = set(re.findall(r"\]\(docs/([\w-]+\.md)[)#]", README))
    unlinked = {path.name for path in DOCS} - linked
    assert not unlinked, f"docs/ pages the README does not link: {sorted(unlinked)}"


def _anchors(text: str) -> set[str]:
    """GitHub's anchors of a page's headings: lower case, punctuation dropped, spaces to hyphens."""
    headings = re.findall(r"^#+ (.+)$", re.sub(r"```.*?```", "", text, flags=re.DOTALL), re.MULTILINE)
    return {re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-") for heading in headings}


@pytest.mark.parametrize("page", sorted(PAGES), ids=lambda path: path.name)
def test_relative_links_lead_to_files_and_headings_that_exist(page: Path):
    for target, anchor in re.findall(r"\]\(([^)#\s]*)(?:#([^)\s]*))?\)", PAGES[page]):
        if "://" in target:
            continue
        linked = (page.parent / target).resolve() if target else page
        assert linked.exists(), f"{page.name} links {target}, which does not exist"
        if anchor and linked.suffix == ".md":
            headings = _anchors(linked.read_text(encoding="utf-8"))
            assert anchor in headings, f"{page.name}: no heading #{anchor} in {target or page.name}"


def test_the_pages_show_registered_commands():
    assert set(readme_commands()) <= set(SCRIPTS)


# Every registered command, shown or not: a server started by --help used to spin, waiting for a
# lifecycle manager (nav-slam, map_saver_server).
@pytest.mark.parametrize("command", sorted(SCRIPTS))
def test_each_command_imports_answers_help_and_is_tested(command: str):
    module_name, function_name = SCRIPTS[command].split(":")
    assert callable(getattr(importlib.import_module(module_name), function_name))
    code = ("import sys; from importlib import import_module; "
            f"sys.argv = [{command!r}, '--help']; import_module({module_name!r}).{function_name}()")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=REPO)
    assert done.returncode == 0, f"{command} --help failed:\n{done.stdout}\n{done.stderr}"
    assert "usage" in (done.stdout + done.stderr).lower()
    this_file = Path(__file__).resolve()
    users = [path for path in (REPO / "tests").rglob("*.py") if path.resolve() != this_file
             and (command in path.read_text() or module_name in path.read_text())]
    assert users, f"no test runs {command} ({module_name})"
