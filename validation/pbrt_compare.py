#!/usr/bin/env python3
"""Renders pbrt-v4 scene files with pbrt-v4 and with this program and compares the images (issue 33).

For every *.pbrt in --scenes (not its subfolders: those hold included files), both programs render
the file twice, with two seeds, at the same spp. Per scene the report gives:

* the mean luminance (Rec. 709 Y of the linear sRGB pixels) of each program's image (the mean of
  its two renders), their ratio ours/pbrt and the 1-sigma noise of that ratio;
* a map of BLOCK x BLOCK pixel blocks: the relative difference of block luminance
  r = (Y_ours - Y_pbrt) / Y_pbrt, with the median and 90th percentile of |r| over blocks;
* the noise level: the same statistic for the two programs' own noise. For each block the two
  renders of one program differ by noise alone, so n = ((Yo1 - Yo2)^2 + (Yp1 - Yp2)^2) / 4 is an
  unbiased estimate of the variance of Y_ours - Y_pbrt (each the mean of two renders). The noise
  level is the median over blocks of sqrt(n) / Y_pbrt. When the two programs agree in expectation,
  median |r| is about 0.8 of it (Gaussian noise: 0.674 sigma against sqrt(ln 2) sigma); the verdict
  calls a scene "within noise" when median |r| <= 1.25 x the noise level;
* the mean CIEDE2000 over blocks (block mean linear sRGB -> XYZ -> CIELAB, D65 white, luminance
  scaled so that the 95th percentile of pbrt's block Y is L* = 100), beside the same number for
  pbrt's two renders against each other (its noise floor: single renders, so somewhat larger than
  the noise in the averaged comparison).

Blocks darker than 1 % of the pbrt image's mean luminance in both images are left out of the
relative statistics (their relative difference is noise over nothing); the report says how many.

Writes into --out (default validation/results): pbrt_compare.md (the table and the command that
made it), pbrt_compare.json (the numbers), pbrt_compare/<scene>.png (pbrt | ours | relative
difference map) and keeps the renders in --renders (default build/pbrt_compare; with --reuse,
renders already there are not made again).

    python validation/pbrt_compare.py --spp 256 [--only NAME[,NAME]] [--threads 2]

A scene may ask for more samples than --spp with a comment line `# pbrt_compare: spp x4`.
Renders run under `nice -n 10`, one at a time, with --threads threads (default 2).
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import subprocess
import sys
import warnings
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message='"SciPy" related API')

sys.path.insert(0, str(Path(__file__).resolve().parent))
from conftest import pathtracer_location, repo_root_path  # noqa: E402
from pfm import read_pfm  # noqa: E402

ROOT = repo_root_path()
DEFAULT_PBRT = Path("/work/pbrt/build/pbrt")
REC709_Y = np.array([0.2126, 0.7152, 0.0722])
WITHIN_NOISE = 1.25  # median |r| / noise level above which a scene is called a disagreement
DARK_FRACTION = 0.01


@dataclass
class SceneResult:
    scene: str
    spp: int
    error: str = ""  # why the comparison could not be made (a program refused the file)
    ours_stderr: list[str] = field(default_factory=list)
    mean_y_pbrt: float = float("nan")
    mean_y_ours: float = float("nan")
    ratio: float = float("nan")  # mean_y_ours / mean_y_pbrt
    ratio_sigma: float = float("nan")  # 1-sigma noise of the ratio
    block_median: float = float("nan")  # median over blocks of |r|
    block_p90: float = float("nan")
    block_signed_median: float = float("nan")  # median of r (sign: + ours brighter)
    noise: float = float("nan")  # median over blocks of the relative noise of Y_ours - Y_pbrt
    blocks_used: int = 0
    blocks_dark: int = 0
    delta_e: float = float("nan")
    delta_e_pbrt_self: float = float("nan")
    delta_e_ours_self: float = float("nan")

    @property
    def within_noise(self) -> bool:
        return bool(self.block_median <= WITHIN_NOISE * self.noise)

    @property
    def mean_within_1pc(self) -> bool:
        return bool(abs(self.ratio - 1.0) <= 0.01)


def scene_spp(scene: Path, spp: int) -> int:
    match = re.search(r"^#\s*pbrt_compare:\s*spp\s*x\s*(\d+)", scene.read_text(), re.MULTILINE)
    return spp * int(match.group(1)) if match else spp


def run(command: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["nice", "-n", "10", *command], cwd=cwd, capture_output=True, text=True)


def render_pbrt(pbrt: Path, scene: Path, spp: int, seed: int, threads: int, out: Path) -> str:
    """Renders with pbrt-v4; returns an error message, or "" on success."""
    result = run([str(pbrt), "--nthreads", str(threads), "--spp", str(spp), "--seed", str(seed),
                  "--outfile", str(out), str(scene)], scene.parent)
    if result.returncode != 0 or not out.is_file():
        return f"pbrt-v4 exit {result.returncode}: {last_line(result.stderr + result.stdout)}"
    return ""


def render_ours(program: Path, scene: Path, spp: int, seed: int, threads: int, out: Path) -> tuple[str, list[str]]:
    """Renders with this program; returns (error message or "", the lines it wrote on stderr)."""
    result = run([str(program), str(scene), "--spp", str(spp), "--seed", str(seed), "--threads", str(threads),
                  "--quiet", "-o", str(out)], scene.parent)
    # Messages name the scene relative to its folder, so reports do not depend on the checkout's place.
    lines = [line.replace(str(scene.parent) + "/", "") for line in result.stderr.splitlines() if line.strip()]
    if result.returncode != 0 or not out.is_file():
        return f"ours exit {result.returncode}: {last_line(result.stderr)}", lines
    return "", lines


def last_line(text: str) -> str:
    """The first line that says "Error" (pbrt-v4 prints a banner first), else the last line."""
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", line).strip() for line in text.splitlines() if line.strip()]
    errors = [line for line in lines if "error" in line.lower()]
    return (errors or lines or ["(no message)"])[0 if errors else -1]


def luminance(img: np.ndarray) -> np.ndarray:
    return img @ REC709_Y


def block_means(img: np.ndarray, block: int) -> np.ndarray:
    """(H/block, W/block, C) means over block x block pixels (the image cropped to whole blocks)."""
    h, w = img.shape[0] // block * block, img.shape[1] // block * block
    img = img[:h, :w]
    return img.reshape(h // block, block, w // block, block, -1).mean(axis=(1, 3))


def lab_blocks(rgb_blocks: np.ndarray, white_y: float) -> np.ndarray:
    import colour

    space = colour.RGB_COLOURSPACES["sRGB"]
    xyz = np.einsum("ij,...j->...i", space.matrix_RGB_to_XYZ, rgb_blocks) / white_y
    return colour.XYZ_to_Lab(xyz, space.whitepoint)


def mean_delta_e(a_blocks: np.ndarray, b_blocks: np.ndarray, white_y: float) -> float:
    import colour

    return float(np.mean(colour.delta_E(lab_blocks(a_blocks, white_y), lab_blocks(b_blocks, white_y),
                                        method="CIE 2000")))


def compare(result: SceneResult, p1: np.ndarray, p2: np.ndarray, o1: np.ndarray, o2: np.ndarray,
            block: int) -> np.ndarray:
    """Fills result's numbers; returns the block map of r (NaN where dark)."""
    if p1.shape != o1.shape:
        result.error = f"image sizes differ: pbrt {p1.shape[1]}x{p1.shape[0]}, ours {o1.shape[1]}x{o1.shape[0]}"
        return np.full((1, 1), np.nan)
    pm, om = (p1 + p2) / 2, (o1 + o2) / 2
    yp, yo = luminance(pm), luminance(om)
    result.mean_y_pbrt, result.mean_y_ours = float(yp.mean()), float(yo.mean())
    result.ratio = result.mean_y_ours / result.mean_y_pbrt

    bp, bo = block_means(yp[..., None], block)[..., 0], block_means(yo[..., None], block)[..., 0]
    dp = block_means(luminance(p1 - p2)[..., None], block)[..., 0]
    do = block_means(luminance(o1 - o2)[..., None], block)[..., 0]
    variance = (dp ** 2 + do ** 2) / 4  # unbiased estimate of var(bo - bp) per block
    result.ratio_sigma = float(np.sqrt(variance.sum()) / variance.size / bp.mean())

    floor = DARK_FRACTION * result.mean_y_pbrt
    lit = np.maximum(bp, bo) >= floor
    denominator = np.maximum(bp, floor)
    r = np.where(lit, (bo - bp) / denominator, np.nan)
    noise = np.sqrt(variance) / denominator
    result.blocks_used, result.blocks_dark = int(lit.sum()), int((~lit).sum())
    if lit.any():
        result.block_median = float(np.median(np.abs(r[lit])))
        result.block_p90 = float(np.percentile(np.abs(r[lit]), 90))
        result.block_signed_median = float(np.median(r[lit]))
        result.noise = float(np.median(noise[lit]))

    white_y = float(np.percentile(bp, 95)) or float(bp.max()) or 1.0
    rgb = [block_means(x, block) for x in (pm, om, p1, p2, o1, o2)]
    result.delta_e = mean_delta_e(rgb[0], rgb[1], white_y)
    result.delta_e_pbrt_self = mean_delta_e(rgb[2], rgb[3], white_y)
    result.delta_e_ours_self = mean_delta_e(rgb[4], rgb[5], white_y)
    return r


def display(img: np.ndarray, white_y: float) -> np.ndarray:
    x = np.clip(img / white_y, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def write_figure(path: Path, name: str, pbrt_img: np.ndarray, ours_img: np.ndarray | None, r: np.ndarray | None,
                 result: SceneResult) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    white_y = float(np.percentile(luminance(pbrt_img), 99)) or 1.0
    fig, axes = plt.subplots(1, 3, figsize=(9, 3.3), dpi=72)
    axes[0].imshow(display(pbrt_img, white_y), interpolation="nearest")
    axes[0].set_title("pbrt-v4", fontsize=9)
    if ours_img is not None and ours_img.shape == pbrt_img.shape:
        axes[1].imshow(display(ours_img, white_y), interpolation="nearest")
    axes[1].set_title("ours", fontsize=9)
    if r is not None and r.size > 1:
        shown = axes[2].imshow(r, cmap="RdBu_r", vmin=-0.2, vmax=0.2, interpolation="nearest")
        fig.colorbar(shown, ax=axes[2], fraction=0.046, pad=0.04)
        axes[2].set_title(f"(ours - pbrt) / pbrt, blocks; median |r| {result.block_median:.3f}", fontsize=8)
    else:
        axes[2].set_title("no comparison", fontsize=9)
        axes[2].text(0.5, 0.5, result.error[:60], ha="center", va="center", fontsize=6, wrap=True)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(name, fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=72)
    plt.close(fig)
    tmp.replace(path)


def fmt(x: float, spec: str) -> str:
    return "-" if x != x else format(x, spec)


def markdown(results: list[SceneResult], command: str, args: argparse.Namespace, block: int) -> str:
    lines = [
        "# pbrt-v4 against this program, scene by scene",
        "",
        f"Made by `{command}`",
        "",
        f"pbrt-v4: `{args.pbrt}`; ours: `{args.program}`{' (' + args.program_label + ')' if args.program_label else ''}; seeds {args.seeds[0]} and {args.seeds[1]} per program "
        f"(each program's image is the mean of its two renders); {block}x{block}-pixel blocks.",
        "",
        "Columns: mean Rec. 709 luminance of each image; ours/pbrt with its 1-sigma noise; the median and 90th "
        "percentile over blocks of |r| = |Y_ours - Y_pbrt| / Y_pbrt and the signed median of r; the noise level "
        "(median over blocks of the combined 1-sigma relative noise, from each program's two seeds; pure noise "
        f"gives median |r| about 0.8 of it); verdict: `ok` when |ratio - 1| <= 1 % and median |r| <= "
        f"{WITHIN_NOISE} x noise; mean CIEDE2000 over blocks, beside pbrt's own two renders against each other.",
        "",
        "| scene | spp | Y pbrt | Y ours | ours/pbrt | ±1σ | median \\|r\\| | p90 \\|r\\| | median r | noise | verdict "
        "| ΔE00 | ΔE00 pbrt self |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|",
    ]
    for res in results:
        if res.error:
            lines.append(f"| {res.scene} | {res.spp} | {fmt(res.mean_y_pbrt, '.4g')} | - | - | - | - | - | - | - | "
                         f"not compared | - | - |")
            continue
        verdict = []
        if not res.mean_within_1pc:
            verdict.append("mean")
        if not res.within_noise:
            verdict.append("blocks")
        lines.append(
            f"| {res.scene} | {res.spp} | {res.mean_y_pbrt:.4g} | {res.mean_y_ours:.4g} | {res.ratio:.4f} | "
            f"{res.ratio_sigma:.2g} | {fmt(res.block_median, '.4f')} | {fmt(res.block_p90, '.4f')} | "
            f"{fmt(res.block_signed_median, '+.4f')} | {fmt(res.noise, '.4f')} | "
            f"{'ok' if not verdict else 'DIFFERS (' + ', '.join(verdict) + ')'} | {res.delta_e:.2f} | "
            f"{res.delta_e_pbrt_self:.2f} |")
    notes = [res for res in results if res.error or res.ours_stderr]
    if notes:
        lines += ["", "## Messages", ""]
        for res in notes:
            if res.error:
                lines.append(f"- **{res.scene}**: not compared: `{res.error}`")
            for line in res.ours_stderr[:5]:
                lines.append(f"- {res.scene}: ours said `{line}`")
    lines += ["", "Side-by-side pictures (pbrt-v4 | ours | block map of r, blue: ours darker, red: ours brighter, "
              "±20 %): `pbrt_compare/<scene>.png`.", ""]
    return "\n".join(lines)


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pbrt", type=Path, default=DEFAULT_PBRT, help="pbrt-v4 binary")
    parser.add_argument("--program", type=Path, default=pathtracer_location(), help="this renderer's binary")
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--seeds", type=lambda s: [int(x) for x in s.split(",")], default=[1, 2],
                        help="two seeds, comma-separated (default 1,2)")
    parser.add_argument("--scenes", type=Path, default=ROOT / "validation" / "pbrt_scenes")
    parser.add_argument("--only", action="append", default=[], help="scene name(s) (file stem), comma-separated")
    parser.add_argument("--out", type=Path, default=ROOT / "validation" / "results")
    parser.add_argument("--renders", type=Path, default=ROOT / "build" / "pbrt_compare")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--program-label", default="", help="what --program was built from (written into the report)")
    parser.add_argument("--block", type=int, default=8)
    parser.add_argument("--reuse", action="store_true", help="keep renders that already exist in --renders")
    args = parser.parse_args(argv)
    if len(args.seeds) != 2 or args.seeds[0] == args.seeds[1]:
        parser.error("--seeds takes two different seeds")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    only = {name for item in args.only for name in item.split(",") if name}
    scenes = sorted(p for p in args.scenes.glob("*.pbrt") if not only or p.stem in only)
    if not scenes:
        print(f"pbrt_compare: no scenes in {args.scenes}" + (f" named {sorted(only)}" if only else ""), file=sys.stderr)
        return 1
    args.renders.mkdir(parents=True, exist_ok=True)
    results: list[SceneResult] = []
    for scene in scenes:
        name = scene.stem
        spp = scene_spp(scene, args.spp)
        res = SceneResult(scene=name, spp=spp)
        images: dict[str, list[np.ndarray]] = {"pbrt": [], "ours": []}
        for seed in args.seeds:
            for who in ("pbrt", "ours"):
                out = args.renders / f"{name}.{who}.spp{spp}.seed{seed}.pfm"
                said = out.with_suffix(".stderr.txt")  # what ours wrote, kept for --reuse
                if args.reuse and out.is_file() and who == "ours" and said.is_file():
                    res.ours_stderr = said.read_text().splitlines()
                if not (args.reuse and out.is_file()):
                    out.unlink(missing_ok=True)
                    if who == "pbrt":
                        error = render_pbrt(args.pbrt.resolve(), scene.resolve(), spp, seed, args.threads, out)
                    else:
                        error, lines = render_ours(args.program.resolve(), scene.resolve(), spp, seed, args.threads, out)
                        res.ours_stderr = lines
                        said.write_text("".join(line + "\n" for line in lines))
                    if error:
                        res.error = res.error or error
                        continue
                images[who].append(read_pfm(out))
        r = None
        if not res.error:
            r = compare(res, *images["pbrt"], *images["ours"], block=args.block)
        if images["pbrt"]:
            pbrt_img = sum(images["pbrt"]) / len(images["pbrt"])
            res.mean_y_pbrt = float(luminance(pbrt_img).mean())
            ours_img = sum(images["ours"]) / len(images["ours"]) if images["ours"] else None
            write_figure(args.out / "pbrt_compare" / f"{name}.png", name, pbrt_img, ours_img, r, res)
        results.append(res)
        status = res.error or (f"ours/pbrt {res.ratio:.4f} ±{res.ratio_sigma:.4f}, median |r| {res.block_median:.4f} "
                               f"(noise {res.noise:.4f}), dE {res.delta_e:.2f}")
        print(f"{name}: {status}", flush=True)

    command = "python validation/pbrt_compare.py " + shlex.join(argv if argv is not None else sys.argv[1:])
    args.out.mkdir(parents=True, exist_ok=True)
    for path, text in ((args.out / "pbrt_compare.md", markdown(results, command, args, args.block)),
                       (args.out / "pbrt_compare.json",
                        json.dumps([asdict(r) | {"within_noise": r.within_noise} for r in results], indent=1))):
        tmp = path.with_suffix(path.suffix + ".tmp")
        tmp.write_text(text + "\n")
        tmp.replace(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
