"""scripts/repeatability.py (docs/architecture.md, "What repeats"): where two recordings of a run part.

Two synthetic runs (tests/helpers/bag_synthetic.py) with the same seed are the same run recorded
twice: the script says so, ends with the verdict "identical" and exits 0. Another seed changes only
AMCL's estimates: the script names /amcl_pose, its first stamp (sim time 100 s), ends with
"differ: first part at sim time 100.000 s on /amcl_pose" and exits 1, while the ground truth agrees.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.helpers.bag_synthetic import write_synthetic_run

SCRIPT = Path(__file__).resolve().parents[3] / "scripts" / "repeatability.py"


def _compare(a: Path, b: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(SCRIPT), str(a), str(b), "--topics", "/ground_truth",
                           "/amcl_pose"], capture_output=True, text=True, timeout=60)


def test_the_same_run_recorded_twice_agrees_and_a_changed_estimate_is_named(tmp_path: Path) -> None:
    first, again, other = tmp_path / "a.mcap", tmp_path / "b.mcap", tmp_path / "c.mcap"
    write_synthetic_run(first, seed=7)
    write_synthetic_run(again, seed=7)
    write_synthetic_run(other, seed=8)
    same = _compare(first, again)
    assert same.returncode == 0, same.stdout + same.stderr
    differs = _compare(first, other)
    assert differs.returncode == 1, differs.stdout + differs.stderr
    lines = {line.split()[0]: line for line in differs.stdout.splitlines() if line.startswith("/")}
    assert "first differs at stamp 100.000 s" in lines["/amcl_pose"], differs.stdout
    assert "identical" in lines["/ground_truth"], differs.stdout
    # the verdict, last: one word first, then where and at which sim time the runs part
    assert same.stdout.splitlines()[-1].startswith("identical: 2 topics"), same.stdout
    assert differs.stdout.splitlines()[-1] == "differ: first part at sim time 100.000 s on /amcl_pose", \
        differs.stdout
