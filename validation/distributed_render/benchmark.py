"""Overhead of distribution (not a test): one render on a LocalCluster of two single-threaded
workers against one two-threaded process, for a short and a long render.

    python validation/distributed_render/benchmark.py [--pathtracer build/pathtracer]

overhead = (cluster time − single-process time) / single-process time, where the cluster time
runs from planning the passes to the merged image (scheduling, two processes per part start,
film transfer to this process, merge); the cluster's start-up is reported apart. Each render
is run `--repeat` times, alternating, and the medians are compared. Checks the two images are
bit-identical.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from distributed import Client, LocalCluster  # noqa: E402

from distributed_render import render  # noqa: E402

RENDERS = {
    # cornell at 256x256: passes of 61 spp (4M paths)
    "short": ["cornell", "--width", "256", "--height", "256", "--spp", "244", "--seed", "1"],
    "long": ["cornell", "--width", "256", "--height", "256", "--spp", "1952", "--seed", "1"],
}


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--pathtracer", default=str(Path(__file__).resolve().parents[2] / "build" / "pathtracer"))
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--parts", type=int, default=4, help="tasks per render (default: 2 per worker)")
    opts = p.parse_args()
    t0 = time.monotonic()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(cluster)
    client.wait_for_workers(2)
    print(f"LocalCluster of 2 single-threaded workers started in {time.monotonic() - t0:.2f} s")
    with tempfile.TemporaryDirectory() as tmp, client, cluster:
        for name, args in RENDERS.items():
            single_times, cluster_times = [], []
            for _ in range(opts.repeat):
                one = Path(tmp) / "one.pfm"
                t = time.monotonic()
                subprocess.run([opts.pathtracer, *args, "--threads", "2", "--quiet", "-o", str(one)], check=True)
                single_times.append(time.monotonic() - t)
                merged = Path(tmp) / "merged.pfm"
                t = time.monotonic()
                render(client, [*args, "--threads", "1"], [str(merged)], pathtracer=opts.pathtracer,
                       parts=opts.parts, progress=None)
                cluster_times.append(time.monotonic() - t)
                assert merged.read_bytes() == one.read_bytes(), "the images differ"
            s, c = statistics.median(single_times), statistics.median(cluster_times)
            print(f"{name:5s} {' '.join(args)}: one process {s:.2f} s, cluster {c:.2f} s "
                  f"(runs: {', '.join(f'{x:.2f}' for x in cluster_times)}), overhead {100 * (c - s) / s:+.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
