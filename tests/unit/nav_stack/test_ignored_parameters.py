"""Every name in a parameter dataclass's IGNORED table is one of its fields, and the docs list it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from nav_stack.core.costmap.params import StaticLayerParams
from nav_stack.core.localization.params import AmclParams

DOCS = Path(__file__).resolve().parents[3] / "docs" / "nav2-differences.md"


@pytest.mark.parametrize("cls", [AmclParams, StaticLayerParams])
def test_ignored_names_are_fields_and_documented(cls):
    fields = {f.name for f in dataclasses.fields(cls)}
    docs = DOCS.read_text()
    assert cls.IGNORED, f"{cls.__name__} lists no ignored parameter"
    for name, why in cls.IGNORED.items():
        assert name in fields, f"{cls.__name__}.IGNORED names {name!r}, which is no field"
        assert why, f"{cls.__name__}.IGNORED[{name!r}] gives no reason"
        assert f"`{name}`" in docs, f"docs/nav2-differences.md does not list {name}"
