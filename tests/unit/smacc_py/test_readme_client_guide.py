"""docs/smacc2-guide.md's "Writing your own client" shows exactly the code that the tests run."""

from __future__ import annotations

import re
from pathlib import Path

from smacc_py.examples import writing_clients

REPO = Path(__file__).resolve().parents[3]


def _readme_code() -> str:
    guide = (REPO / "docs" / "smacc2-guide.md").read_text(encoding="utf-8")
    section = guide.split("\n## Writing your own client\n", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.DOTALL)
    assert len(blocks) == 1, "the section should hold one Python block"
    return blocks[0]


def _example_code() -> str:
    source = Path(writing_clients.__file__).read_text(encoding="utf-8")
    return source.split("# README:begin\n", 1)[1].split("# README:end\n", 1)[0]


def test_the_readme_block_is_the_example_module_verbatim() -> None:
    assert _readme_code() == _example_code()


def test_the_readme_block_runs_and_defines_the_clients_and_behaviors() -> None:
    namespace: dict[str, object] = {}
    exec(compile(_readme_code(), "docs/smacc2-guide.md", "exec"), namespace)
    for name in ("ClWait", "CbWaitFor", "CbWaitForServerAsync", "ClThermometer", "CbWaitHot",
                 "CbFirstReadingAsync"):
        assert name in namespace, name
