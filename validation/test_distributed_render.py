"""The Dask driver (validation/distributed_render) on a LocalCluster of two workers renders
an image bit-identical to one process, also when a worker is killed during the render (its
temporary folder is removed) or a part's process fails (the task is retried); the program's
own one-line error reaches the user, without a Python traceback."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import pytest

distributed = pytest.importorskip("distributed")
from distributed import Client, LocalCluster  # noqa: E402

from distributed_render import RenderError, render, split_passes  # noqa: E402

# Passes of 4e6 / (200 * 100) = 200 spp: 4 passes of about a second each on one thread.
RENDER = ["cornell", "--width", "200", "--height", "100", "--spp", "800", "--max-depth", "2",
          "--seed", "8", "--threads", "1"]


@pytest.fixture(scope="module")
def reference(pathtracer, tmp_path_factory) -> bytes:
    out = tmp_path_factory.mktemp("one") / "one.pfm"
    import subprocess
    subprocess.run([str(pathtracer), *RENDER, "--quiet", "-o", str(out)], check=True)
    return out.read_bytes()


@pytest.fixture
def client():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        with Client(cluster) as c:
            yield c


def test_split_passes_covers_every_pass_once():
    for passes in (1, 4, 7, 100):
        for parts in (1, 2, 3, 7, 200):
            ranges = split_passes(passes, parts)
            assert ranges[0][0] == 0 and ranges[-1][1] == passes
            assert all(a < b for a, b in ranges)
            assert all(ranges[k][1] == ranges[k + 1][0] for k in range(len(ranges) - 1))


def test_cluster_render_is_bit_identical(client, pathtracer, reference, tmp_path):
    out = tmp_path / "merged.pfm"
    parts = render(client, RENDER, [str(out)], pathtracer=str(pathtracer), parts=4, progress=None)
    assert len({p.worker for p in parts}) == 2, "both workers rendered parts"
    assert out.read_bytes() == reference


def test_uploaded_binary_renders_the_same(client, pathtracer, reference, tmp_path):
    out = tmp_path / "merged.pfm"
    render(client, RENDER, [str(out)], pathtracer=str(pathtracer), parts=2, upload_binary=True,
           progress=None)
    assert out.read_bytes() == reference


def test_killed_worker_part_is_rendered_again(client, pathtracer, reference, tmp_path):
    """SIGKILL one worker while it renders a part: Dask reschedules the task (the nanny
    restarts the worker) and the merged image is still the single-process one."""
    killed: dict[str, object] = {}

    def kill_a_busy_worker():
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            busy = {w: keys for w, keys in client.processing().items() if keys}
            if busy:
                time.sleep(0.3)  # inside the part's render
                worker = sorted(busy)[0]
                pid = client.run(os.getpid, workers=[worker])[worker]
                killed["tasks"] = client.processing()[worker]
                killed["pid"] = pid
                os.kill(pid, signal.SIGKILL)
                killed["worker"] = worker
                return
            time.sleep(0.02)

    killer = threading.Thread(target=kill_a_busy_worker)
    killer.start()
    out = tmp_path / "merged.pfm"
    parts = render(client, RENDER, [str(out)], pathtracer=str(pathtracer), parts=4, progress=None)
    killer.join()
    assert killed.get("worker"), "a worker was killed during the render"
    assert killed["tasks"], "it was rendering a part when killed"
    assert sorted(p.passes for p in parts) == [(0, 1), (1, 2), (2, 3), (3, 4)]
    assert out.read_bytes() == reference
    # The killed worker could not remove its part's folder: the driver did.
    killed_pid = killed["pid"]
    left = list(Path(tempfile.gettempdir()).glob(f"spt-part-{killed_pid}-*"))
    assert not left, left


def test_failed_part_process_is_retried(client, pathtracer, reference, tmp_path):
    """A part whose program fails (here: exit 3 the first time any part runs) is retried."""
    marker = tmp_path / "failed-once"
    wrapper = tmp_path / "flaky-pathtracer"
    wrapper.write_text(
        "#!/bin/sh\n"
        f'case " $* " in *" --passes "*) [ -e "{marker}" ] || {{ touch "{marker}"; exit 3; }};; esac\n'
        f'exec "{pathtracer}" "$@"\n')
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    out = tmp_path / "merged.pfm"
    render(client, RENDER, [str(out)], pathtracer=str(wrapper), parts=2, retries=2, progress=None)
    assert marker.exists(), "one part failed"
    assert out.read_bytes() == reference


def test_program_errors_reach_the_user_without_a_traceback(pathtracer, tmp_path):
    """The command line prints the program's message and exits with its status."""
    def driver(*args):
        return subprocess.run([sys.executable, "-m", "distributed_render", "--workers", "1",
                               "--pathtracer", str(pathtracer), "--", *args],
                              cwd=Path(__file__).resolve().parent, capture_output=True, text=True)
    bad_scene = driver("no-such-scene", "-o", str(tmp_path / "x.png"))
    assert bad_scene.returncode == 2, bad_scene.stderr
    assert "pathtracer: SCENE: expected a scene file (.json or .pbrt) or one of" in bad_scene.stderr
    assert "Traceback" not in bad_scene.stderr
    bad_output = driver("cornell", "--width", "8", "--height", "8", "--spp", "1",
                        "-o", str(tmp_path / "no-such-folder" / "x.png"))
    assert bad_output.returncode == 1, bad_output.stderr
    assert f"cannot write '{tmp_path / 'no-such-folder' / 'x.png'}'" in bad_output.stderr
    assert "Traceback" not in bad_output.stderr


def test_part_that_keeps_failing_raises_the_programs_message(client, pathtracer, tmp_path):
    wrapper = tmp_path / "broken-pathtracer"
    wrapper.write_text('#!/bin/sh\n'
                       'case " $* " in *" --passes "*) echo "pathtracer: out of luck" >&2; exit 3;; esac\n'
                       f'exec "{pathtracer}" "$@"\n')
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    with pytest.raises(RenderError, match=r"^passes \d+:\d+ on .*: pathtracer: out of luck$") as error:
        render(client, RENDER, [str(tmp_path / "x.pfm")], pathtracer=str(wrapper), parts=2, retries=1,
               progress=None)
    assert error.value.exit_code == 3
    assert not (tmp_path / "x.pfm").exists()
