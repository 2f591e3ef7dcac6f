#!/usr/bin/env python3
"""How each PNG tone curve renders every built-in scene: clipped and dark pixels, brightness.

For every scene of ``pathtracer --list-scenes`` it renders the scene at its default spp (and
``--scale``, default 0.5 to keep it quick; the statistics are per pixel, so they do not depend
on the size) once per display setting, all with the same seed, so every PNG comes from the very
same film:

* ``--tonemap clip`` (the only behaviour before tone curves), ``--tonemap neutral`` (the
  default), ``--tonemap pbr-neutral``, and ``neutral`` with ``--auto-exposure`` (its stops are
  read from the summary).

Reported per PNG: **clipped**, the % of pixels with a channel at 255; **mean**, the mean 8-bit
code over all channels ("dull" when it falls); **dark**, the % of pixels whose brightest
channel is at most 10. A measurement, not a test: it writes ``tone_map_survey.md`` to
``--out`` and exits non-zero only if a render fails.

    .venv/bin/python validation/tone_map_survey.py                    # about 3 min, 2 cores
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent))
from conftest import pathtracer_location, repo_root_path  # noqa: E402

SETTINGS = {  # column label -> extra flags
    "clip": ["--tonemap", "clip"],
    "neutral (default)": ["--tonemap", "neutral"],
    "pbr-neutral": ["--tonemap", "pbr-neutral"],
    "neutral + auto exposure": ["--tonemap", "neutral", "--auto-exposure"],
}
DARK_CODE = 10


def png_stats(path: Path) -> tuple[float, float, float]:
    codes = np.asarray(Image.open(path).convert("RGB"), dtype=int)
    clipped = 100.0 * (codes == 255).any(axis=-1).mean()
    dark = 100.0 * (codes.max(axis=-1) <= DARK_CODE).mean()
    return clipped, float(codes.mean()), dark


def survey(program: Path, scale: float, seed: int, workdir: Path) -> list[dict]:
    scenes = subprocess.run([str(program), "--list-scenes"], check=True, capture_output=True,
                            text=True).stdout.split()
    rows = []
    for scene in scenes:
        row = {"scene": scene}
        for index, (label, flags) in enumerate(SETTINGS.items()):
            out = workdir / f"{scene}-{index}.png"
            command = [str(program), scene, "--scale", str(scale), "--seed", str(seed),
                       "-o", str(out)] + flags
            result = subprocess.run(command, capture_output=True, text=True)
            if result.returncode != 0:
                raise RuntimeError(f"{' '.join(command)} failed:\n{result.stderr}")
            row[label] = png_stats(out)
            size = re.search(r": (\d+x\d+), (\d+) spp", result.stderr)
            row["size"] = f"{size[1]}, {size[2]} spp" if size else "?"
            stops = re.search(r"auto exposure: ([-+]\d+\.\d) stops", result.stderr)
            if stops:
                row["auto stops"] = stops[1]
            clipped, mean, dark = row[label]
            print(f"{scene:16s} {label:24s} clipped {clipped:5.1f} %  mean {mean:5.1f}"
                  f"  dark {dark:5.1f} %", flush=True)
        rows.append(row)
    return rows


def markdown(rows: list[dict], program: Path, scale: float, seed: int) -> str:
    lines = ["# PNG tone curves on the built-in scenes\n",
             f"`validation/tone_map_survey.py --scale {scale} --seed {seed}` with `{program}`: "
             "each scene at its default spp; per PNG, % of pixels with a channel at 255 "
             f"(clipped), mean 8-bit code (mean), % of pixels with every channel <= {DARK_CODE} "
             "(dark). All PNGs of a scene come from the same film (same seed).\n",
             "| scene | size | " + " | ".join(f"{s}: clipped / mean / dark" for s in SETTINGS)
             + " | auto exposure |",
             "|---|---|" + "---|" * len(SETTINGS) + "---|"]
    for row in rows:
        cells = [f"{row[s][0]:.1f} % / {row[s][1]:.0f} / {row[s][2]:.1f} %" for s in SETTINGS]
        lines.append(f"| `{row['scene']}` | {row['size']} | " + " | ".join(cells)
                     + f" | {row.get('auto stops', '?')} stops |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--program", type=Path, default=pathtracer_location())
    parser.add_argument("--scale", type=float, default=0.5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, default=repo_root_path() / "validation" / "results")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        rows = survey(args.program, args.scale, args.seed, Path(tmp))
    text = markdown(rows, args.program, args.scale, args.seed)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "tone_map_survey.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
