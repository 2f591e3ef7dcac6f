"""Command line: python -m distributed_render [driver options] -- SCENE [render flags] -o OUT...

  --scheduler ADDR     a running Dask scheduler (tcp://host:8786); default: a LocalCluster
  --workers N          LocalCluster workers (default 2), --threads-per-worker T (default 1)
  --render-threads T   pathtracer --threads for each part (default: the worker's threads)
  --parts N            tasks (default: two per worker thread)
  --pathtracer PATH    the program (default: build/pathtracer of this repository)
  --upload-binary, --upload-scene   send the program / the scene file to the workers
  --keep-parts DIR     keep the partial films there
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from distributed import Client, LocalCluster

from .driver import RenderError, render


def main(argv: list[str]) -> int:
    if "--" not in argv:
        print(__doc__, file=sys.stderr)
        return 2
    split = argv.index("--")
    p = argparse.ArgumentParser(prog="python -m distributed_render")
    p.add_argument("--scheduler")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--threads-per-worker", type=int, default=1)
    p.add_argument("--render-threads", type=int)
    p.add_argument("--parts", type=int)
    p.add_argument("--pathtracer", default=str(Path(__file__).resolve().parents[2] / "build" / "pathtracer"))
    p.add_argument("--upload-binary", action="store_true")
    p.add_argument("--upload-scene", action="store_true")
    p.add_argument("--keep-parts")
    opts = p.parse_args(argv[:split])
    rest = argv[split + 1:]
    outputs, render_args, i = [], [], 0
    while i < len(rest):
        if rest[i] in ("-o", "--output") and i + 1 < len(rest):
            outputs.append(rest[i + 1])
            i += 2
        else:
            render_args.append(rest[i])
            i += 1
    if not outputs:
        print("distributed_render: expected -o FILE after --", file=sys.stderr)
        return 2
    threads = opts.render_threads or opts.threads_per_worker
    render_args += ["--threads", str(threads)]
    if opts.scheduler:
        client = Client(opts.scheduler)
    else:
        client = Client(LocalCluster(n_workers=opts.workers, threads_per_worker=opts.threads_per_worker))
    with client:
        print(f"dashboard: {client.dashboard_link}", file=sys.stderr)
        try:
            render(client, render_args, outputs, pathtracer=opts.pathtracer, parts=opts.parts,
                   upload_binary=opts.upload_binary, upload_scene=opts.upload_scene,
                   keep_parts=opts.keep_parts, progress=lambda m: print(m, file=sys.stderr))
        except RenderError as e:  # the program's own message says what is wrong: no traceback
            print(e, file=sys.stderr)
            return e.exit_code
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
