"""Writes the two texture files of the imagemap scenes (numpy and the standard library only).

texture_linear.pfm (linear float) and texture_srgb.png (8-bit, sRGB-encoded) hold the same 16x16
pattern: four coloured quadrants, a grey ramp along the bottom row, and a red 3x3 marker at the
top-left corner (texture coordinates u = 0, v = 1), so a flip in either axis shows.

    python validation/pbrt_scenes/make_textures.py
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SIZE = 16


def pattern() -> np.ndarray:
    """Linear RGB reflectances, shape (16, 16, 3), row 0 = top of the image (v = 1)."""
    img = np.empty((SIZE, SIZE, 3))
    half = SIZE // 2
    img[:half, :half] = (0.65, 0.65, 0.15)  # top-left quadrant: yellow
    img[:half, half:] = (0.15, 0.55, 0.65)  # top-right: teal
    img[half:, :half] = (0.6, 0.2, 0.6)  # bottom-left: purple
    img[half:, half:] = (0.75, 0.75, 0.75)  # bottom-right: light grey
    img[-1, :] = np.linspace(0.05, 0.9, SIZE)[:, None]  # bottom row: grey ramp, dark at u = 0
    img[:3, :3] = (0.8, 0.05, 0.05)  # the marker
    return img


def write_pfm(path: Path, img: np.ndarray) -> None:
    h, w, _ = img.shape
    header = f"PF\n{w} {h}\n-1\n".encode()
    path.write_bytes(header + img[::-1].astype("<f4").tobytes())  # PFM rows run bottom to top


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def write_png(path: Path, img8: np.ndarray) -> None:
    h, w, _ = img8.shape
    raw = b"".join(b"\x00" + img8[row].tobytes() for row in range(h))  # filter type 0 per row

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)  # 8-bit RGB, no interlace
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9))
                     + chunk(b"IEND", b""))


def main(out_dir: Path = HERE) -> None:
    img = pattern()
    write_pfm(out_dir / "texture_linear.pfm", img)
    write_png(out_dir / "texture_srgb.png", np.round(srgb_encode(img) * 255).astype(np.uint8))


if __name__ == "__main__":
    main()
