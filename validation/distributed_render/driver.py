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


class RenderError(RuntimeError):
    """The program failed: the message is its own one-line error (and where it ran).
    `exit_code` is the program's exit status."""

    def __init__(self, message: str, exit_code: int = 1):
        super().__init__(message)
        self.exit_code = exit_code

    def __reduce__(self):  # from a worker to the driver with its exit status
        return (RenderError, (str(self), self.exit_code))


def _run_program(cmd: Sequence[str], where: str = "", **kwargs) -> subprocess.CompletedProcess:
    """Runs the program; raises RenderError with its message (stderr) when it fails."""
    proc = subprocess.run(list(cmd), capture_output=True, text=True, **kwargs)
    if proc.returncode != 0:
        message = proc.stderr.strip() or f"{Path(cmd[0]).name} exited with status {proc.returncode}"
        raise RenderError(f"{where}{message}", proc.returncode)
    return proc


def plan_passes(pathtracer: str, render_args: Sequence[str]) -> int:
    """How many passes the render has (``pathtracer ARGS --print-passes``)."""
    out = _run_program([pathtracer, *render_args, "--print-passes"]).stdout
    fields = dict(line.split() for line in out.splitlines())
    return int(fields["passes"])


_PART_DIR_PREFIX = "spt-part-"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_orphaned_part_folders() -> int:
    """Removes the part folders (spt-part-<pid>-*) in this machine's temporary folder whose
    worker process is gone (a killed worker cannot clean up after itself). Returns how many."""
    removed = 0
    for folder in Path(tempfile.gettempdir()).glob(f"{_PART_DIR_PREFIX}*-*"):
        pid = folder.name[len(_PART_DIR_PREFIX):].split("-", 1)[0]
        if pid.isdigit() and not _pid_alive(int(pid)):
            shutil.rmtree(folder, ignore_errors=True)
            removed += 1
    return removed


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
    remove_orphaned_part_folders()
    # Named after this process, so that a later task or the driver removes it if the worker
    # is killed before it can.
    with tempfile.TemporaryDirectory(prefix=f"{_PART_DIR_PREFIX}{os.getpid()}-") as work:
        if scene is not None:
            (Path(work) / scene[0]).write_bytes(scene[1])
        film = Path(work) / "part.film"
        cmd = [_worker_binary(binary, pathtracer), *render_args, "--passes",
               f"{passes[0]}:{passes[1]}", "-o", str(film), "--quiet"]
        _run_program(cmd, f"passes {passes[0]}:{passes[1]} on {worker}: ", cwd=work,
                     preexec_fn=_die_with_parent if sys.platform == "linux" else None)
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
    Returns the parts (which worker rendered what, how long it took). Raises RenderError with
    the program's message when the render cannot be planned, a part still fails after its
    retries, or the merge fails.
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
    try:
        for done, future in enumerate(as_completed(futures), start=1):
            part = future.result()
            results.append(part)
            if progress:
                progress(f"part {done}/{len(ranges)}: passes {part.passes[0]}:{part.passes[1]} of {passes} "
                         f"on {part.worker} in {part.seconds:.1f} s")
    finally:
        client.cancel(futures)
        # The folders of workers killed during the render (their tasks ran again elsewhere).
        client.run(remove_orphaned_part_folders)
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
        _run_program(cmd + ["--quiet"])
        if progress:
            progress(f"merged {len(files)} parts into {', '.join(outputs)}")
    finally:
        if not keep_parts:
            shutil.rmtree(parts_dir, ignore_errors=True)
    return results
