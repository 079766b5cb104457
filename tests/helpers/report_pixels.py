"""Pixel statistics of run-report PNGs: is a series drawn, and is the picture more than a blank frame.

A report that renders but draws nothing (an empty recording, a topic the extractor no longer
finds) is still a valid PNG of the right size; these counts tell it apart from one that shows a run.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.image import imread

from navsuite_tools.report.render import UNKNOWN_RGB


def load_rgb(png: Path) -> np.ndarray:
    """The image as an H×W×3 array of 0..255 ints (alpha dropped)."""
    return (imread(png)[:, :, :3] * 255).round().astype(int)


def pixels_near(rgb: np.ndarray, hex_color: str, tolerance: int = 12) -> int:
    """How many pixels are within ``tolerance`` (per channel) of ``#rrggbb``."""
    target = np.array([int(hex_color[i:i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(rgb - target).max(axis=-1) <= tolerance).sum())


def content_fraction(rgb: np.ndarray) -> float:
    """Share of pixels that are neither white paper nor the map panel's unknown-area tint."""
    pixels = rgb.reshape(-1, 3).astype(int)
    backgrounds = [np.array([255, 255, 255]), np.round(np.array(UNKNOWN_RGB) * 255)]
    distance = np.min([np.abs(pixels - bg).max(axis=1) for bg in backgrounds], axis=0)
    return float((distance > 30).mean())


def distinct_colors(rgb: np.ndarray) -> int:
    """Number of different colours in the image (anti-aliased drawings have many)."""
    return len(np.unique(rgb.reshape(-1, 3), axis=0))
