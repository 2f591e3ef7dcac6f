"""Writes the meshes of the built-in scene liquid-glass (scenes/liquid-glass-*.ply): a
drinking glass as a solid of revolution, split where the liquid touches it.

  liquid-glass-dry.ply   glass against air: outside, base, rim, and the inner wall above
                         the liquid (faces point out of the glass)
  liquid-glass-wet.ply   glass against liquid: inner wall below the liquid level and the
                         inner floor (faces point out of the glass, into the liquid)
  liquid-glass-top.ply   the liquid's free surface (faces point up, out of the liquid)

Together the first two close the glass; the last two close the liquid. The rings of all
three share their vertices, so the pieces meet without gaps.

    python3 tools/make_liquid_glass.py
"""
import math
import pathlib

SEGMENTS = 64
OUTER_R, INNER_R = 0.34, 0.30
HEIGHT, BASE, LEVEL = 1.0, 0.08, 0.62


def ring(r, y):
    return [(r * math.cos(2 * math.pi * k / SEGMENTS), y, r * math.sin(2 * math.pi * k / SEGMENTS))
            for k in range(SEGMENTS)]


def lathe(profile):
    """Triangles of the surface swept by the polyline profile [(r, y), ...] about +y."""
    tris = []
    for (r0, y0), (r1, y1) in zip(profile, profile[1:]):
        a, b = ring(r0, y0), ring(r1, y1)
        for k in range(SEGMENTS):
            k1 = (k + 1) % SEGMENTS
            if r0 > 0:
                tris.append((a[k], a[k1], b[k]))
            if r1 > 0:
                tris.append((a[k1], b[k1], b[k]))
    return tris


def signed_volume(tris):
    return sum((a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                a[2] * (b[0] * c[1] - b[1] * c[0])) for a, b, c in tris) / 6


def write_ply(path, tris):
    verts, index, faces = [], {}, []
    for t in tris:
        face = []
        for v in t:
            key = tuple(round(x, 9) for x in v)
            if key not in index:
                index[key] = len(verts)
                verts.append(key)
            face.append(index[key])
        faces.append(face)
    lines = ["ply", "format ascii 1.0", "comment written by tools/make_liquid_glass.py",
             f"element vertex {len(verts)}", "property float x", "property float y", "property float z",
             f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    lines += [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in verts]
    lines += ["3 " + " ".join(map(str, f)) for f in faces]
    path.write_text("\n".join(lines) + "\n")


def flipped(tris):
    return [(a, c, b) for a, b, c in tris]


def main():
    dry = lathe([(0, 0), (OUTER_R, 0), (OUTER_R, HEIGHT), (INNER_R, HEIGHT), (INNER_R, LEVEL)])
    wet = lathe([(INNER_R, LEVEL), (INNER_R, BASE), (0, BASE)])
    # Orient the glass (dry + wet) outward: positive signed volume.
    if signed_volume(dry + wet) < 0:
        dry, wet = flipped(dry), flipped(wet)
    # The liquid's surface: a fan on the level ring, facing up.
    top = [((0, LEVEL, 0), b, a) for a, b in zip(ring(INNER_R, LEVEL), ring(INNER_R, LEVEL)[1:] + ring(INNER_R, LEVEL)[:1])]
    a, b, c = top[0]
    normal_y = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2])
    if normal_y < 0:
        top = flipped(top)
    scenes = pathlib.Path(__file__).resolve().parent.parent / "scenes"
    write_ply(scenes / "liquid-glass-dry.ply", dry)
    write_ply(scenes / "liquid-glass-wet.ply", wet)
    write_ply(scenes / "liquid-glass-top.ply", top)
    print("glass volume", signed_volume(dry + wet), "liquid volume", -signed_volume(wet) + signed_volume(top))


if __name__ == "__main__":
    main()
