"""Compare two recordings of the same lockstep run and name the first sim time where they differ.

Why: issue 17 asks that a seed mission give the same result on every run. A mission that ends
SUCCESS once and ABORT the next diverged somewhere long before; this tool finds where
(navsuite_tools/bag/compare.py does the work: stamped topics lined up by header stamp, unstamped ones by
order, the first difference beyond ``--tol`` per topic).

Usage::

    python scripts/repeatability.py RUN_A.mcap RUN_B.mcap [--tol 1e-9] [--topics /odom /cmd_vel]

Each argument may also be a scenario output directory (the ``run.mcap`` under it is found).
The last line is the verdict: ``identical`` (every compared topic agrees over the common span, and
each has messages in common) or ``differ``, naming the earliest sim time at which the recordings
part and on which topic (or the topics that one recording lacks). Exit status 0 for ``identical``,
1 for ``differ``. ``navsuite-scenarios rerun RUN_DIR NAME`` runs a scenario again and compares the
two recordings the same way.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from navsuite_tools.bag.compare import DEFAULT_TOPICS, compare_recordings


def _mcap(arg: str) -> Path:
    path = Path(arg)
    if path.is_dir():
        found = sorted(path.rglob("*.mcap"))
        if len(found) != 1:
            raise SystemExit(f"{path}: expected one .mcap under it, found {len(found)}")
        return found[0]
    return path


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--tol", type=float, default=1e-9, help="largest difference taken as equal")
    parser.add_argument("--topics", nargs="+", default=list(DEFAULT_TOPICS))
    args = parser.parse_args(argv)
    result = compare_recordings(_mcap(args.a), _mcap(args.b), args.topics, args.tol)
    if result.report:
        print(result.report)
    print(result.verdict)
    return 0 if result.identical else 1


if __name__ == "__main__":
    sys.exit(main())
