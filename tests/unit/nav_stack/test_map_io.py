"""map_server yaml + pgm loading and map_saver output, against hand-computed tiny grids."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nav_stack.core.map_io import LoadMapResult, MapLoadError, OccupancyMap, load_map, save_map

# Image rows as stored in the file (top row first). Shades are pixel/255.
IMAGE = [[0, 254, 205], [128, 10, 255]]


def write_pgm(path: Path, rows: list[list[int]], ascii_: bool = False, maxval: int = 255) -> None:
    height, width = len(rows), len(rows[0])
    if ascii_:
        body = "\n".join(" ".join(str(v) for v in row) for row in rows)
        path.write_text(f"P2\n# a comment\n{width} {height}\n{maxval}\n{body}\n")
        return
    dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
    path.write_bytes(
        f"P5\n# c\n{width} {height}\n{maxval}\n".encode() + np.array(rows, dtype=dtype).tobytes()
    )


def write_yaml(path: Path, image: str = "map.pgm", **overrides: object) -> Path:
    fields: dict[str, object] = {
        "image": image,
        "resolution": 0.1,
        "origin": "[1.0, -2.0, 0.5]",
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    fields.update(overrides)
    text = "".join(f"{k}: {v}\n" for k, v in fields.items() if v is not None)
    path.write_text(text)
    return path


@pytest.fixture
def map_dir(tmp_path: Path) -> Path:
    write_pgm(tmp_path / "map.pgm", IMAGE)
    return tmp_path


def test_trinary_thresholds_flip_rows_and_geometry(map_dir: Path) -> None:
    loaded = load_map(write_yaml(map_dir / "map.yaml"))
    # occ = 1 - shade: 0→1.0 (100), 254→0.004 (0), 205→0.19608 (not < 0.196: -1), 128→0.498 (-1),
    # 10→0.96 (100), 255→0 (0).
    expected_image = [[100, 0, -1], [-1, 100, 0]]
    assert loaded.data.tolist() == expected_image[::-1]
    assert loaded.data.dtype == np.int8
    spec = loaded.spec
    assert (spec.width, spec.height, spec.resolution) == (3, 2, 0.1)
    assert (spec.origin_x, spec.origin_y, spec.origin_yaw) == (1.0, -2.0, 0.5)


def test_negate_inverts_shades(map_dir: Path) -> None:
    loaded = load_map(write_yaml(map_dir / "map.yaml", negate=1))
    # occ = shade: 0→0 (0), 254→0.996 (100), 205→0.804 (100), 128→0.502 (-1), 10→0.039 (0), 255→1 (100).
    assert loaded.data.tolist() == [[-1, 0, 100], [0, 100, 100]]
    assert load_map(write_yaml(map_dir / "b.yaml", negate="true")).data.tolist() == loaded.data.tolist()


def test_scale_mode_interpolates_between_thresholds(map_dir: Path) -> None:
    loaded = load_map(write_yaml(map_dir / "map.yaml", mode="scale"))
    # 128: occ 0.49804 → rint((0.49804 - 0.196) / 0.454 · 100) = 67; 205: occ 0.196078 → rint(0.017) = 0.
    assert loaded.data.tolist() == [[67, 100, 0], [100, 0, 0]]


def test_raw_mode_keeps_pixel_values_0_to_100(tmp_path: Path) -> None:
    write_pgm(tmp_path / "raw.pgm", [[0, 50, 100], [101, 255, 7]])
    loaded = load_map(write_yaml(tmp_path / "map.yaml", image="raw.pgm", mode="raw", negate=1))
    assert loaded.data.tolist() == [[-1, -1, 7], [0, 50, 100]]


def test_ascii_and_16_bit_pgm_match_binary(map_dir: Path, tmp_path: Path) -> None:
    binary = load_map(write_yaml(map_dir / "map.yaml")).data
    write_pgm(tmp_path / "ascii.pgm", IMAGE, ascii_=True)
    assert load_map(write_yaml(tmp_path / "a.yaml", image="ascii.pgm")).data.tolist() == binary.tolist()
    write_pgm(tmp_path / "wide.pgm", [[v * 257 for v in row] for row in IMAGE], maxval=65535)
    assert load_map(write_yaml(tmp_path / "w.yaml", image="wide.pgm")).data.tolist() == binary.tolist()


def test_image_path_is_relative_to_the_yaml(tmp_path: Path) -> None:
    (tmp_path / "maps" / "img").mkdir(parents=True)
    write_pgm(tmp_path / "maps" / "img" / "m.pgm", IMAGE)
    loaded = load_map(write_yaml(tmp_path / "maps" / "m.yaml", image="img/m.pgm"))
    assert loaded.image_path == tmp_path / "maps" / "img" / "m.pgm"
    absolute = load_map(write_yaml(tmp_path / "abs.yaml", image=str(tmp_path / "maps" / "img" / "m.pgm")))
    assert absolute.data.tolist() == loaded.data.tolist()


@pytest.mark.parametrize(
    ("overrides", "code", "fragment"),
    [
        ({"resolution": None}, LoadMapResult.INVALID_MAP_METADATA, "'resolution'"),
        ({"resolution": -0.05}, LoadMapResult.INVALID_MAP_METADATA, "-0.05"),
        ({"origin": "[1.0, 2.0]"}, LoadMapResult.INVALID_MAP_METADATA, "'origin'"),
        ({"negate": "maybe"}, LoadMapResult.INVALID_MAP_METADATA, "'maybe'"),
        ({"free_thresh": None}, LoadMapResult.INVALID_MAP_METADATA, "'free_thresh'"),
        ({"occupied_thresh": "high"}, LoadMapResult.INVALID_MAP_METADATA, "'high'"),
        ({"mode": "fancy"}, LoadMapResult.INVALID_MAP_METADATA, "'fancy'"),
        ({"image": None}, LoadMapResult.INVALID_MAP_METADATA, "'image'"),
        ({"image": "absent.pgm"}, LoadMapResult.INVALID_MAP_DATA, "absent.pgm"),
    ],
)
def test_bad_metadata_reports_code_file_field_and_value(
    map_dir: Path, overrides: dict[str, object], code: LoadMapResult, fragment: str
) -> None:
    yaml_path = write_yaml(map_dir / "bad.yaml", **overrides)
    with pytest.raises(MapLoadError) as err:
        load_map(yaml_path)
    assert err.value.code == code
    assert fragment in str(err.value)
    assert str(map_dir) in str(err.value)


def test_missing_yaml_is_map_does_not_exist(tmp_path: Path) -> None:
    with pytest.raises(MapLoadError) as err:
        load_map(tmp_path / "nope.yaml")
    assert err.value.code == LoadMapResult.MAP_DOES_NOT_EXIST
    assert "nope.yaml" in err.value.message
    with pytest.raises(MapLoadError) as empty:
        load_map("")
    assert empty.value.code == LoadMapResult.MAP_DOES_NOT_EXIST


def test_unreadable_images_are_invalid_map_data(tmp_path: Path) -> None:
    (tmp_path / "map.png").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(20))
    with pytest.raises(MapLoadError) as png:
        load_map(write_yaml(tmp_path / "p.yaml", image="map.png"))
    assert png.value.code == LoadMapResult.INVALID_MAP_DATA
    assert "PNG" in png.value.message
    (tmp_path / "short.pgm").write_bytes(b"P5\n4 4\n255\n" + bytes(5))
    with pytest.raises(MapLoadError) as short:
        load_map(write_yaml(tmp_path / "s.yaml", image="short.pgm"))
    assert short.value.code == LoadMapResult.INVALID_MAP_DATA
    assert "truncated" in short.value.message


def _grid(values: list[list[int]]) -> OccupancyMap:
    from nav_stack.core.grid import GridSpec

    data = np.array(values, dtype=np.int8)
    return OccupancyMap(data, GridSpec(data.shape[1], data.shape[0], 0.05, -1.5, 2.0, 0.25))


def test_save_writes_trinary_pixels_and_yaml(tmp_path: Path) -> None:
    occ = _grid([[0, 100, -1], [20, 30, 70]])
    yaml_path, pgm_path = save_map(occ, tmp_path / "saved")
    raw = pgm_path.read_bytes()
    pixels = np.frombuffer(raw[-6:], dtype=np.uint8).reshape(2, 3)
    # image top row = grid row 1; ≤ 25 → 254, ≥ 65 → 0, else/unknown → 205.
    assert pixels.tolist() == [[254, 205, 0], [254, 0, 205]]
    text = yaml_path.read_text()
    assert "image: saved.pgm" in text and "mode: trinary" in text and "negate: 0" in text
    # Classified with free 0.25, but the yaml says 0.196 so unknown pixels reload as unknown.
    assert "free_thresh: 0.196" in text and "occupied_thresh: 0.65" in text
    reloaded = load_map(yaml_path)
    assert reloaded.data.tolist() == [[0, 100, -1], [0, -1, 100]]  # 20 → free, 30 → unknown, 70 → occ


def test_save_then_load_round_trips_with_ros1_free_threshold(tmp_path: Path) -> None:
    occ = _grid([[0, 100, -1], [0, -1, 100]])
    yaml_path, _ = save_map(occ, tmp_path / "rt", free_thresh=0.196)
    loaded = load_map(yaml_path)
    assert loaded.data.tolist() == occ.data.tolist()
    assert math.isclose(loaded.spec.origin_yaw, 0.25) and loaded.spec.origin_x == -1.5


def test_save_refuses_to_overwrite_unless_asked(tmp_path: Path) -> None:
    occ = _grid([[0, 100, -1]])
    save_map(occ, tmp_path / "m")
    with pytest.raises(FileExistsError, match=r"m\.pgm"):
        save_map(occ, tmp_path / "m")
    save_map(_grid([[100, 100, 100]]), tmp_path / "m", overwrite=True, free_thresh=0.196)
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[100, 100, 100]]
    with pytest.raises(ValueError, match="free_thresh"):
        save_map(occ, tmp_path / "x", free_thresh=0.7)


def test_turtlebot3_world_map_loads_if_present() -> None:
    path = Path(__file__).resolve().parents[3] / "maps" / "turtlebot3_world.yaml"
    if not path.exists():
        pytest.skip("maps/turtlebot3_world.yaml not generated yet")
    loaded = load_map(path)
    assert set(np.unique(loaded.data).tolist()) <= {-1, 0, 100}
    assert (loaded.data == 100).sum() > 100 and (loaded.data == 0).sum() > 1000
