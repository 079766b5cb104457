"""The guard that ends what a test left running (tests/helpers/process_tree.py)."""

from __future__ import annotations

import os
import subprocess
import sys

from tests.helpers.process_tree import child_pids, kill_leftovers, live_children


def test_a_process_started_after_the_snapshot_is_killed_and_named() -> None:
    before = live_children(os.getpid())
    kept = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    before_kept = live_children(os.getpid())
    left = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(121)"], start_new_session=True)
    try:
        assert {kept.pid, left.pid} <= set(child_pids(os.getpid())) and kept.pid not in before
        killed = kill_leftovers(before_kept)
        assert [line.split(":")[0] for line in killed] == [str(left.pid)]
        assert "time.sleep(121)" in killed[0]
        assert left.pid not in live_children(os.getpid())
        assert kept.pid in live_children(os.getpid())  # in the snapshot: left alone
    finally:
        kept.kill()
        kept.wait()
        left.kill()
        left.wait()  # reaped by the guard already: Popen takes that as an exit
