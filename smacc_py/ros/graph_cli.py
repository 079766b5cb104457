"""``smacc-graph <sm> [--format mermaid|dot] [-o file]``: a machine's graph from its declarations alone.

No ROS node is created and no state is entered: the graph comes from the classes (states, transitions
with tags, orthogonals with their behaviors, reactors, generators). The machine is named as for
``smacc-run`` (a shipped name, a module path, a .py file or a package folder; ``smacc_py.ros.loader``).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path


def main(argv: Sequence[str] | None = None) -> int:
    from smacc_py.core import InvalidDefinitionError, to_dot, to_mermaid
    from smacc_py.ros.loader import load_state_machine

    parser = argparse.ArgumentParser(prog="smacc-graph", description=__doc__.splitlines()[0])
    parser.add_argument("state_machine", help="sm_nav2_test_1, a module path, a .py file or package folder, "
                                              "optionally followed by :ClassName")
    parser.add_argument("--format", choices=("mermaid", "dot"), default="mermaid")
    parser.add_argument("-o", "--output", type=Path, help="write here instead of stdout")
    options = parser.parse_args(argv)
    try:
        sm_type = load_state_machine(options.state_machine)
        text = (to_mermaid if options.format == "mermaid" else to_dot)(sm_type)
    except (ValueError, InvalidDefinitionError) as error:
        print(f"smacc-graph: {error}", file=sys.stderr)
        return 2
    if options.output is None:
        sys.stdout.write(text)
    else:
        options.output.write_text(text)
        print(f"smacc-graph: wrote {options.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
