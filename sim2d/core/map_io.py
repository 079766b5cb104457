"""sim2d's own reader and writer of map_server maps (YAML + PGM).

Why its own: the simulator is an independent model of the world (docs/architecture.md, rule 2). If sim2d
and nav_stack shared one loader, a flipped axis or an off-by-one origin would be invisible.

Conventions (map_server, Nav2 Jazzy): pixel row 0 is the top of the image (largest y); the
origin [x, y, yaw] is the pose of the lower-left pixel's corner in the map frame (m, rad);
with negate 0 a pixel's occupancy probability is p = (255 - pixel) / 255, occupied when
p > occupied_thresh, free when p < free_thresh, else unknown.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray

FREE_PIXEL = 254
UNKNOWN_PIXEL = 205
OCCUPIED_PIXEL = 0


@dataclass(frozen=True)
class MapImage:
    """A loaded map.

    Attributes:
        occupied: (H, W) bool, row 0 = lowest y (already flipped from image order).
        resolution: cell size (m).
        origin: (x, y) of the lower-left corner of cell [0, 0] in the map frame (m).
    """

    occupied: NDArray[np.bool_]
    resolution: float
    origin: tuple[float, float]


def _field(meta: dict[str, Any], key: str, path: Path, kind: type) -> Any:
    if key not in meta:
        raise ValueError(f"{path}: missing field '{key}'")
    value = meta[key]
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if not isinstance(value, kind):
        raise ValueError(f"{path}: field '{key}' must be {kind.__name__}, got {value!r}")
    return value


def read_pgm(path: Path) -> NDArray[np.uint8]:
    """Read a binary (P5) or ASCII (P2) 8-bit PGM into an (H, W) uint8 array in image row order."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ValueError(f"{path}: cannot read image ({exc.strerror})") from exc
    tokens: list[bytes] = []
    pos = 0
    while len(tokens) < 4:  # magic, width, height, maxval; '#' starts a comment
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.find(b"\n", pos) + 1 or len(data)
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            raise ValueError(f"{path}: truncated PGM header")
        tokens.append(data[start:pos])
    magic = tokens[0]
    try:
        width, height, maxval = (int(t) for t in tokens[1:])
    except ValueError as exc:
        raise ValueError(f"{path}: bad PGM header {tokens!r}") from exc
    if magic not in (b"P5", b"P2") or maxval > 255 or width <= 0 or height <= 0:
        raise ValueError(f"{path}: only 8-bit P5/P2 PGM images are supported (header {tokens!r})")
    if magic == b"P5":
        pixels = np.frombuffer(data, dtype=np.uint8, count=width * height, offset=pos + 1) \
            if len(data) >= pos + 1 + width * height else None
    else:
        values = np.array(data[pos:].split(), dtype=np.int64)
        pixels = values.astype(np.uint8) if len(values) == width * height else None
    if pixels is None:
        raise ValueError(f"{path}: image data shorter than {width}x{height}")
    return pixels.reshape(height, width)


def load_map(yaml_path: str | Path) -> MapImage:
    """Load a map_server YAML and its image; errors name the file and the field."""
    path = Path(yaml_path)
    try:
        meta = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ValueError(f"{path}: cannot read map YAML ({exc})") from exc
    if not isinstance(meta, dict):
        raise ValueError(f"{path}: expected a mapping with 'image', 'resolution', 'origin'")
    image_name = _field(meta, "image", path, str)
    resolution = _field(meta, "resolution", path, float)
    origin = _field(meta, "origin", path, list)
    occupied_thresh = float(meta.get("occupied_thresh", 0.65))
    negate = int(meta.get("negate", 0))
    mode = str(meta.get("mode", "trinary"))
    if resolution <= 0.0:
        raise ValueError(f"{path}: field 'resolution' must be > 0, got {resolution}")
    if len(origin) != 3 or not all(isinstance(v, (int, float)) for v in origin):
        raise ValueError(f"{path}: field 'origin' must be [x, y, yaw], got {origin!r}")
    if abs(float(origin[2])) > 1e-9:
        raise ValueError(f"{path}: field 'origin' yaw must be 0 for sim2d, got {origin[2]}")
    if mode not in ("trinary", "scale", "raw"):
        raise ValueError(f"{path}: field 'mode' must be trinary, scale or raw, got {mode!r}")
    pixels = read_pgm(path.parent / image_name).astype(np.float64)
    if mode == "raw":
        occupied = pixels >= occupied_thresh * 100.0
    else:
        p = pixels / 255.0 if negate else (255.0 - pixels) / 255.0
        occupied = p > occupied_thresh
    return MapImage(occupied[::-1].copy(), resolution, (float(origin[0]), float(origin[1])))


def write_map(yaml_path: str | Path, image: NDArray[np.uint8], resolution: float,
              origin: tuple[float, float], header: str = "") -> None:
    """Write a trinary map_server pair: ``image`` (H, W) in image row order, next to the YAML."""
    path = Path(yaml_path)
    pgm = path.with_suffix(".pgm")
    height, width = image.shape
    pgm.write_bytes(f"P5\n{width} {height}\n255\n".encode() + np.ascontiguousarray(image).tobytes())
    meta = {"image": pgm.name, "mode": "trinary", "resolution": resolution,
            "origin": [round(origin[0], 6), round(origin[1], 6), 0.0],
            "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}
    path.write_text(header + yaml.safe_dump(meta, sort_keys=False, default_flow_style=None))
