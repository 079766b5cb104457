"""Load and save occupancy maps in the map_server format (yaml metadata + pgm image).

Why: map_server, AMCL and the global costmap must read a map exactly as Nav2's map_io does, so a
map made for Nav2 (turtlebot3_world, a map_saver output) means the same here. Semantics follow
nav2_map_server/map_io.cpp (Jazzy):

* yaml keys ``image`` (relative paths are relative to the yaml), ``resolution`` (m/cell), ``origin``
  ``[x, y, yaw]`` (m, m, rad), ``negate`` (int or bool), ``occupied_thresh``, ``free_thresh`` are
  required; ``mode`` is optional (``trinary`` by default, or ``scale`` / ``raw``).
* a pixel's shade is ``gray / maxval`` in [0, 1]; occupancy ``occ = shade`` if negate else
  ``1 - shade``. trinary: ``occ > occupied_thresh`` → 100, ``occ < free_thresh`` → 0, else -1.
  scale: the same ends, in between ``rint((occ - free) / (occupied - free) · 100)``. raw: the pixel
  value ``round(shade · 255)`` itself when it is 0..100, else -1 (negate ignored).
* image row 0 is the top; OccupancyGrid row 0 is the bottom, so rows are flipped.

Only PGM images are read and written (binary P5 and ascii P2, 8 or 16 bit): PNG/BMP need an image
library (Pillow), which the project does not depend on; such a file fails with INVALID_MAP_DATA.
Scale mode's transparency (alpha = unknown) cannot occur in a pgm, so every pixel counts as opaque.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml

from nav_stack.core.grid import GridSpec

OccupancyArray = npt.NDArray[np.int8]


class LoadMapResult(enum.IntEnum):
    """nav2_msgs/srv/LoadMap result codes."""

    SUCCESS = 0
    MAP_DOES_NOT_EXIST = 1
    INVALID_MAP_DATA = 2
    INVALID_MAP_METADATA = 3
    UNDEFINED_FAILURE = 255


class MapMode(enum.Enum):
    """How pixel shades become occupancy values (map_server ``mode``)."""

    TRINARY = "trinary"
    SCALE = "scale"
    RAW = "raw"


class MapLoadError(Exception):
    """A map could not be loaded; ``code`` is the LoadMap result a map_server returns for it."""

    def __init__(self, code: LoadMapResult, message: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message


@dataclass(frozen=True)
class OccupancyMap:
    """A loaded map: OccupancyGrid-layout data (row 0 = bottom; 0..100, -1 unknown) and geometry."""

    data: OccupancyArray
    spec: GridSpec
    image_path: Path | None = None

    def __post_init__(self) -> None:
        if self.data.shape != self.spec.shape:
            raise ValueError(f"map data shape {self.data.shape} does not match grid {self.spec.shape}")


@dataclass(frozen=True)
class MapMetadata:
    """The parsed yaml of a map."""

    image: Path
    resolution: float
    origin: tuple[float, float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: MapMode


_META = LoadMapResult.INVALID_MAP_METADATA
_DATA = LoadMapResult.INVALID_MAP_DATA


def _fail(code: LoadMapResult, message: str) -> MapLoadError:
    return MapLoadError(code, message)


def _number(doc: dict[str, object], key: str, path: Path) -> float:
    if key not in doc:
        raise _fail(_META, f"{path}: missing required key '{key}'")
    value = doc[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _fail(_META, f"{path}: '{key}' must be a finite number, got {value!r}")
    return float(value)


def read_map_metadata(yaml_path: str | Path) -> MapMetadata:
    """Parse and check a map yaml; raise MapLoadError (MAP_DOES_NOT_EXIST / INVALID_MAP_METADATA)."""
    path = Path(yaml_path)
    if str(yaml_path) == "":
        raise _fail(LoadMapResult.MAP_DOES_NOT_EXIST, "map yaml file name is empty")
    if not path.is_file():
        raise _fail(LoadMapResult.MAP_DOES_NOT_EXIST, f"map yaml file {path} does not exist")
    try:
        doc = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as exc:
        raise _fail(_META, f"{path}: not valid yaml: {exc}") from exc
    if not isinstance(doc, dict):
        raise _fail(_META, f"{path}: expected a mapping, got {type(doc).__name__}")
    image = doc.get("image")
    if not isinstance(image, str) or not image:
        raise _fail(_META, f"{path}: 'image' must be a non-empty file name, got {image!r}")
    resolution = _number(doc, "resolution", path)
    if resolution <= 0.0:
        raise _fail(_META, f"{path}: 'resolution' must be positive, got {resolution}")
    origin = doc.get("origin")
    if not isinstance(origin, list) or len(origin) != 3:
        raise _fail(LoadMapResult.INVALID_MAP_METADATA,
                    f"{path}: 'origin' must be a list [x, y, yaw] of 3 numbers, got {origin!r}")
    origin_values = [_number({"origin": v}, "origin", path) for v in origin]
    negate = doc.get("negate")
    if negate not in (0, 1):  # True/False compare equal to 1/0, as yaml-cpp accepts int or bool
        raise _fail(_META, f"{path}: 'negate' must be 0, 1, true or false, got {negate!r}")
    occupied = _number(doc, "occupied_thresh", path)
    free = _number(doc, "free_thresh", path)
    mode_name = doc.get("mode", MapMode.TRINARY.value)
    try:
        mode = MapMode(mode_name)
    except ValueError:
        raise _fail(LoadMapResult.INVALID_MAP_METADATA,
                    f"{path}: 'mode' must be one of trinary, scale, raw, got {mode_name!r}") from None
    image_path = Path(image) if Path(image).is_absolute() else path.parent / image
    return MapMetadata(image_path, resolution, (origin_values[0], origin_values[1], origin_values[2]),
                       bool(negate), occupied, free, mode)


def _pgm_tokens(raw: bytes, count: int, path: Path) -> tuple[list[bytes], int]:
    """Read ``count`` whitespace-separated header tokens (skipping # comments); return them and the offset."""
    tokens: list[bytes] = []
    i = 0
    while len(tokens) < count:
        while i < len(raw) and raw[i : i + 1].isspace():
            i += 1
        if i < len(raw) and raw[i : i + 1] == b"#":
            while i < len(raw) and raw[i : i + 1] not in (b"\n", b"\r"):
                i += 1
            continue
        start = i
        while i < len(raw) and not raw[i : i + 1].isspace() and raw[i : i + 1] != b"#":
            i += 1
        if start == i:
            raise _fail(_DATA, f"{path}: truncated pgm header")
        tokens.append(raw[start:i])
    return tokens, i


def read_pgm(path: Path) -> tuple[npt.NDArray[np.float64], int]:
    """Return the image's shades in [0, 1] (row 0 = top row of the file) and its maxval."""
    if not path.is_file():
        raise _fail(_DATA, f"map image {path} does not exist")
    raw = path.read_bytes()
    magic = raw[:2]
    if magic not in (b"P5", b"P2"):
        raise _fail(LoadMapResult.INVALID_MAP_DATA,
                    f"{path}: unsupported image format (magic {magic!r}); only PGM P5/P2 can be read "
                    "(PNG needs Pillow, which is not installed)")
    tokens, offset = _pgm_tokens(raw[2:], 3, path)
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise _fail(_DATA, f"{path}: bad pgm header {tokens!r}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise _fail(_DATA, f"{path}: bad pgm size/maxval {width}x{height}/{maxval}")
    body = raw[2 + offset :]
    if magic == b"P5":
        dtype = np.dtype(np.uint8) if maxval < 256 else np.dtype(">u2")
        expected = width * height * dtype.itemsize
        if len(body) < expected + 1:
            raise _fail(LoadMapResult.INVALID_MAP_DATA,
                        f"{path}: pgm pixel data truncated ({len(body) - 1} of {expected} bytes)")
        pixels = np.frombuffer(body[1 : 1 + expected], dtype=dtype).astype(np.int64)
    else:
        try:
            pixels = np.array([int(t) for t in body.split()], dtype=np.int64)
        except ValueError:
            raise _fail(_DATA, f"{path}: non-numeric pixel in ascii pgm") from None
        if pixels.size != width * height:
            raise _fail(LoadMapResult.INVALID_MAP_DATA,
                        f"{path}: ascii pgm has {pixels.size} pixels, header says {width * height}")
    if pixels.size and int(pixels.max()) > maxval:
        raise _fail(_DATA, f"{path}: pixel value {int(pixels.max())} exceeds maxval {maxval}")
    return pixels.reshape(height, width).astype(np.float64) / maxval, maxval


def occupancy_from_shades(shade: npt.NDArray[np.float64], meta: MapMetadata) -> OccupancyArray:
    """Apply map_server's mode/negate/threshold rules to shades (image layout in, image layout out)."""
    occ = shade if meta.negate else 1.0 - shade
    out = np.full(shade.shape, -1, dtype=np.int8)
    if meta.mode is MapMode.RAW:
        value = np.round(shade * 255.0)
        keep = (value >= 0) & (value <= 100)
        out[keep] = value[keep].astype(np.int8)
        return out
    occupied = meta.occupied_thresh < occ
    free = occ < meta.free_thresh
    if meta.mode is MapMode.SCALE:
        between = ~occupied & ~free
        scaled = np.rint((occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh) * 100.0)
        out[between] = np.clip(scaled[between], -1, 100).astype(np.int8)
    out[occupied] = 100
    out[free] = 0
    return out


def load_map(yaml_path: str | Path) -> OccupancyMap:
    """Load a map_server map; raise MapLoadError carrying the LoadMap result code on any failure."""
    meta = read_map_metadata(yaml_path)
    shade, _ = read_pgm(meta.image)
    data = occupancy_from_shades(shade, meta)[::-1].copy()
    height, width = data.shape
    spec = GridSpec(width, height, meta.resolution, *meta.origin)
    return OccupancyMap(data, spec, meta.image)


#: A yaml free_thresh below the occupancy of unknown pixels (1 − 205/255 = 0.1961) and above that of
#: free ones (0.0039): the value of the TurtleBot3 maps, so a saved trinary map reloads exactly.
UNKNOWN_SAFE_FREE_THRESH = 0.196


def encode_pixels(
    cells: npt.NDArray[np.int8], mode: MapMode, free_thresh: float, occupied_thresh: float
) -> npt.NDArray[np.uint8]:
    """Image (row 0 = top) of OccupancyGrid cells (row 0 = bottom; 0..100, −1 unknown), as map_saver does.

    trinary: cell ≤ rint(100·free_thresh) → 254, cell ≥ rint(100·occupied_thresh) → 0, else 205.
    scale:   known cell c → round(255·(100 − c)/100); unknown → 205 (a pgm has no alpha channel).
    raw:     known cell c → c; unknown → 255 (reloads exactly with ``mode: raw``).
    """
    c = cells.astype(np.int16)[::-1]
    known = (c >= 0) & (c <= 100)
    if mode is MapMode.RAW:
        return np.where(known, c, 255).astype(np.uint8)
    if mode is MapMode.SCALE:
        return np.where(known, np.round(255.0 * (100 - c) / 100.0), 205).astype(np.uint8)
    pixels = np.full(c.shape, 205, dtype=np.uint8)
    pixels[known & (c <= round(free_thresh * 100.0))] = 254
    pixels[known & (c >= round(occupied_thresh * 100.0))] = 0
    return pixels


def save_map(
    occupancy: OccupancyMap,
    map_file_name: str | Path,
    *,
    mode: MapMode = MapMode.TRINARY,
    free_thresh: float = 0.25,
    occupied_thresh: float = 0.65,
    overwrite: bool = False,
) -> tuple[Path, Path]:
    """Write ``<name>.pgm`` (P5) and ``<name>.yaml`` as nav2 map_saver does; return (yaml, pgm) paths.

    The thresholds classify cells (see :func:`encode_pixels`). One deliberate difference from Nav2:
    for trinary maps the yaml's free_thresh is min(free_thresh, UNKNOWN_SAFE_FREE_THRESH). Nav2 writes
    the classification's 0.25, and map_server then reloads unknown pixels (occupancy 0.196) as free;
    here free, unknown and occupied round-trip exactly. Refuses (FileExistsError naming the path) to
    replace existing files unless ``overwrite``.
    """
    if not 0.0 <= free_thresh < occupied_thresh <= 1.0:
        raise ValueError(f"need 0 <= free_thresh < occupied_thresh <= 1, got free_thresh={free_thresh}, "
                         f"occupied_thresh={occupied_thresh}")
    base = Path(map_file_name)
    pgm_path, yaml_path = base.with_name(base.name + ".pgm"), base.with_name(base.name + ".yaml")
    if not overwrite:
        for existing in (pgm_path, yaml_path):
            if existing.exists():
                raise FileExistsError(f"{existing} exists; refusing to overwrite it")
    pixels = encode_pixels(occupancy.data, mode, free_thresh, occupied_thresh)
    spec = occupancy.spec
    header = f"P5\n# CREATOR: nav_stack map_io {spec.resolution:.3f} m/pix\n{spec.width} {spec.height}\n255\n"
    pgm_path.parent.mkdir(parents=True, exist_ok=True)
    pgm_path.write_bytes(header.encode("ascii") + pixels.tobytes())
    yaml_free = min(free_thresh, UNKNOWN_SAFE_FREE_THRESH) if mode is MapMode.TRINARY else free_thresh
    # OccupancyGrid carries a float32 resolution: write its shortest decimal (0.05, not 0.0500000007).
    resolution = float(str(np.float32(spec.resolution)))
    meta = {
        "image": pgm_path.name,
        "mode": mode.value,
        "resolution": resolution,
        "origin": [float(spec.origin_x), float(spec.origin_y), float(spec.origin_yaw)],
        "negate": 0,
        "occupied_thresh": float(occupied_thresh),
        "free_thresh": float(yaml_free),
    }
    yaml_path.write_text(yaml.safe_dump(meta, sort_keys=False, default_flow_style=None))
    return yaml_path, pgm_path
