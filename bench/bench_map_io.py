"""map_server's map loading on a building-sized map: a 2000 x 2000 PGM (100 m x 100 m at 5 cm).

Issue 19 asks that map_server load such a map "in well under a second". The map is issue 19's
benchmark world (bench.worlds.random_obstacle_costmap: 1600 obstacles), written as map_saver
writes it (trinary P5 PGM + YAML) and loaded with nav_stack.core.map_io.load_map, which is what
map_server's configure and its load_map service call: YAML, PGM parse, thresholds into occupancy.

Run: ``.venv/bin/python -m bench.bench_map_io`` (``--no-record`` to only print).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from bench.harness import Benchmark, parse_cli
from bench.worlds import random_obstacle_costmap
from nav_stack.core.map_io import OccupancyMap, load_map, save_map

SIZE = 2000  # cells per side


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("map_io")
    costs, spec = random_obstacle_costmap(SIZE, seed=2, n_obstacles=1600)
    occupancy = np.where(costs == 254, 100, 0).astype(np.int8)
    with tempfile.TemporaryDirectory() as tmp:
        yaml_path, pgm_path = save_map(OccupancyMap(occupancy, spec), Path(tmp) / "warehouse")
        stats = bench.time(f"load a {SIZE}x{SIZE} map (YAML + P5 PGM)", lambda: load_map(yaml_path),
                           repeat=10, warmup=1)
        size_mb = pgm_path.stat().st_size / 1e6
    bench.record(f"map_server load_map, {SIZE}x{SIZE} cells", stats, "ms", scale=1e3,
                 note=f"trinary PGM of {size_mb:.1f} MB, 1600 random obstacles, warm file cache")
    bench.save()


if __name__ == "__main__":
    main()
