"""The Dask driver: split a render's passes, run the parts on workers, merge."""

from __future__ import annotations

import hashlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

from distributed import Client, as_completed


def plan_passes(pathtracer: str, render_args: Sequence[str]) -> int:
    """How many passes the render has (``pathtracer ARGS --print-passes``)."""
    out = subprocess.run([pathtracer, *render_args, "--print-passes"], check=True,
                         capture_output=True, text=True).stdout
    fields = dict(line.split() for line in out.splitlines())
    return int(fields["passes"])


def split_passes(passes: int, parts: int) -> list[tuple[int, int]]:
    """Contiguous ranges [A, B) covering 0..passes, as equal as possible (at most `parts`)."""
    parts = max(1, min(parts, passes))
    cuts = [passes * k // parts for k in range(parts + 1)]
    return [(cuts[k], cuts[k + 1]) for k in range(parts)]


@dataclass
class PartResult:
    passes: tuple[int, int]
    film: bytes
    worker: str
    seconds: float


def _die_with_parent() -> None:
    """In the child: be killed when the worker process dies (Linux), so a killed worker
    leaves no orphaned render behind."""
    try:
        import ctypes
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def _worker_binary(binary: bytes | None, pathtracer: str) -> str:
    """The program on this worker: the uploaded bytes (cached by hash), else the path."""
    if binary is None:
        return pathtracer
    digest = hashlib.sha256(binary).hexdigest()[:16]
    path = Path(tempfile.gettempdir()) / f"spt-pathtracer-{digest}"
    if not path.exists():
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_bytes(binary)
        tmp.chmod(0o755)
        os.replace(tmp, path)
    return str(path)


def render_part(pathtracer: str, render_args: Sequence[str], passes: tuple[int, int],
                binary: bytes | None = None, scene: tuple[str, bytes] | None = None) -> PartResult:
    """Task body (runs on a worker): passes [A, B) into a partial film; returns its bytes.

    `scene` (name, bytes): an uploaded scene file, written as `name` into the part's working
    directory (render_args then names it by that relative name). A failed render raises
    RuntimeError with the program's message, so Dask retries the task.
    """
    from distributed import get_worker
    try:
        worker = get_worker().address
    except ValueError:
        worker = "local"
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="spt-part-") as work:
        if scene is not None:
            (Path(work) / scene[0]).write_bytes(scene[1])
        film = Path(work) / "part.film"
        cmd = [_worker_binary(binary, pathtracer), *render_args, "--passes",
               f"{passes[0]}:{passes[1]}", "-o", str(film), "--quiet"]
        proc = subprocess.run(cmd, cwd=work, capture_output=True, text=True,
                              preexec_fn=_die_with_parent if sys.platform == "linux" else None)
        if proc.returncode != 0:
            raise RuntimeError(f"passes {passes[0]}:{passes[1]} on {worker}: exit {proc.returncode}: "
                               f"{proc.stderr.strip()}")
        return PartResult(passes, film.read_bytes(), worker, time.monotonic() - start)


def render(client: Client, render_args: Sequence[str], outputs: Sequence[str], *,
           pathtracer: str, parts: int | None = None, upload_binary: bool = False,
           upload_scene: bool = False, retries: int = 3, merge_args: Sequence[str] = (),
           keep_parts: str | None = None,
           progress: Callable[[str], None] | None = print) -> list[PartResult]:
    """Renders `render_args` (pathtracer's SCENE and render flags, no -o) on the cluster and
    merges the parts into `outputs` (any image format or .film) on this machine.

    parts: how many tasks (default: two per worker thread, at most one per pass).
    upload_binary: send this machine's pathtracer to the workers (else `pathtracer` must be
    a path valid on every worker). upload_scene: send the scene file (render_args[0]) too.
    retries: how often a task whose process fails is run again (a task whose worker dies
    is rescheduled by Dask itself, up to distributed.scheduler.allowed-failures times).
    Returns the parts (which worker rendered what, how long it took).
    """
    args = list(render_args)
    passes = plan_passes(pathtracer, args)
    if parts is None:
        threads = sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values())
        parts = 2 * max(1, threads)
    ranges = split_passes(passes, parts)
    binary = client.scatter(Path(pathtracer).read_bytes(), broadcast=True) if upload_binary else None
    scene = None
    if upload_scene:
        scene_path = Path(args[0])
        scene = client.scatter((scene_path.name, scene_path.read_bytes()), broadcast=True)
        args[0] = scene_path.name
    futures = [client.submit(render_part, pathtracer, args, r, binary, scene, pure=False, retries=retries,
                             key=f"spt-part-{r[0]}-{r[1]}-{os.urandom(4).hex()}")
               for r in ranges]
    results: list[PartResult] = []
    for done, future in enumerate(as_completed(futures), start=1):
        part = future.result()
        results.append(part)
        if progress:
            progress(f"part {done}/{len(ranges)}: passes {part.passes[0]}:{part.passes[1]} of {passes} "
                     f"on {part.worker} in {part.seconds:.1f} s")
    parts_dir = Path(keep_parts) if keep_parts else Path(tempfile.mkdtemp(prefix="spt-parts-"))
    parts_dir.mkdir(parents=True, exist_ok=True)
    try:
        files = []
        for part in sorted(results, key=lambda p: p.passes):
            path = parts_dir / f"part-{part.passes[0]:06d}-{part.passes[1]:06d}.film"
            path.write_bytes(part.film)
            files.append(str(path))
        cmd = [pathtracer, "merge", *files, *merge_args]
        for out in outputs:
            cmd += ["-o", out]
        subprocess.run(cmd + ["--quiet"], check=True)
        if progress:
            progress(f"merged {len(files)} parts into {', '.join(outputs)}")
    finally:
        if not keep_parts:
            shutil.rmtree(parts_dir, ignore_errors=True)
    return results
