"""Writes the texture files of the imagemap and environment-map scenes (numpy and the standard library only).

texture_linear.pfm (linear float) and texture_srgb.png (8-bit, sRGB-encoded) hold the same 16x16
pattern: four coloured quadrants, a grey ramp along the bottom row, and a red 3x3 marker at the
top-left corner (texture coordinates u = 0, v = 1), so a flip in either axis shows.

envmap_sky.pfm is a 64x64 environment map in pbrt-v4's equal-area octahedral layout (+z up in
the light's space): a dim sky, brighter and bluer towards the zenith, a dark ground half, and a
sun of one texel at 35 degrees elevation that carries about 60 % of the map's flux.

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


def equal_area_square_to_sphere(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Directions of square points (u, v) in [0, 1]^2 under the equal-area octahedral mapping
    (Clarberg 2008) in pbrt-v4's orientation: the centre is +z, the corners -z."""
    a, b = 2 * u - 1, 2 * v - 1
    ap, bp = np.abs(a), np.abs(b)
    signed = 1 - (ap + bp)
    r = 1 - np.abs(signed)
    with np.errstate(invalid="ignore", divide="ignore"):
        phi = np.where(r == 0, 1.0, (bp - ap) / np.where(r == 0, 1, r) + 1) * np.pi / 4
    z = np.copysign(1 - r * r, signed)
    s = r * np.sqrt(np.maximum(2 - r * r, 0))
    return np.stack([np.copysign(np.cos(phi), a) * s, np.copysign(np.sin(phi), b) * s, z], axis=-1)


ENV_SIZE = 64
SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG = 35.0, 60.0


def sky_map() -> np.ndarray:
    """Linear RGB radiance of envmap_sky.pfm, shape (64, 64, 3); row 0 = top of the image,
    texel (x, y) at square point ((x + 0.5) / 64, (y + 0.5) / 64) as pbrt-v4 reads it."""
    c = (np.arange(ENV_SIZE) + 0.5) / ENV_SIZE
    d = equal_area_square_to_sphere(c[None, :], c[:, None])
    up = np.clip(d[..., 2], 0, 1)[..., None]
    sky = (1 - up) * np.array([0.55, 0.6, 0.7]) + up * np.array([0.15, 0.3, 0.8])
    ground = np.array([0.12, 0.1, 0.08])
    img = np.where(d[..., 2:3] > 0, sky, ground)
    el, az = np.radians(SUN_ELEVATION_DEG), np.radians(SUN_AZIMUTH_DEG)
    sun = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    y, x = np.unravel_index(np.argmax(d @ sun), d.shape[:2])
    img[y, x] = np.array([1.0, 0.9, 0.75]) * 2000.0  # one texel: 4 pi / 4096 sr
    return img


def main(out_dir: Path = HERE) -> None:
    img = pattern()
    write_pfm(out_dir / "texture_linear.pfm", img)
    write_png(out_dir / "texture_srgb.png", np.round(srgb_encode(img) * 255).astype(np.uint8))
    write_pfm(out_dir / "envmap_sky.pfm", sky_map())


if __name__ == "__main__":
    main()
