"""The one PFM reader of the Python tools: colour PFM ("PF") files as the renderer writes them."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np


class PfmError(ValueError):
    """A file that is not a well-formed colour PFM image."""


def read_pfm(path: str | Path) -> np.ndarray:
    """float64 array (height, width, 3), row 0 = top of the image (PFM stores rows bottom to top)."""
    path = Path(path)
    data = path.read_bytes()
    # Header: three whitespace-separated tokens, then exactly one whitespace byte.
    tokens: list[bytes] = []
    pos = 0
    while len(tokens) < 4:
        while pos < len(data) and data[pos : pos + 1].isspace():
            pos += 1
        start = pos
        while pos < len(data) and not data[pos : pos + 1].isspace():
            pos += 1
        if start == pos:
            raise PfmError(f"{path}: truncated PFM header")
        tokens.append(data[start:pos])
    pos += 1
    magic, w_tok, h_tok, scale_tok = tokens
    if magic != b"PF":
        raise PfmError(f"{path}: not a colour PFM file (magic {magic!r})")
    try:
        width, height, scale = int(w_tok), int(h_tok), float(scale_tok)
    except ValueError as e:
        raise PfmError(f"{path}: bad PFM header: {e}") from None
    if width <= 0 or height <= 0 or scale == 0 or not math.isfinite(scale):
        raise PfmError(f"{path}: bad PFM header ({width} x {height}, scale {scale})")
    dtype = "<f4" if scale < 0 else ">f4"  # the sign of the scale gives the byte order
    count = width * height * 3
    if len(data) - pos != count * 4:
        raise PfmError(f"{path}: {len(data) - pos} bytes of pixels, expected {count * 4} for {width}x{height}")
    img = np.frombuffer(data, dtype=dtype, count=count, offset=pos).reshape(height, width, 3)
    return img[::-1].astype(np.float64)
