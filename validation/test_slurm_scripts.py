"""The Slurm scripts (validation/distributed_render/slurm) under a stand-in `sbatch` that runs
each job at once, its array tasks in turn, as Slurm would: SLURM_ARRAY_TASK_ID and
SLURM_ARRAY_TASK_COUNT of the submitted array, a job with an `afterok` dependency on a failed
job left pending, --export honoured (ALL or only the listed variables). A render split into
parts merges into the single-process image; a failed task, rerun alone with rerun.sh from a
shell that has none of the submission's variables, renders its own passes (not all of them,
nor the passes of an array of one), and the new merge writes the same image."""

from __future__ import annotations

import json
import os
import subprocess
import textwrap
from pathlib import Path

import pytest

SLURM = Path(__file__).resolve().parent / "distributed_render" / "slurm"

# vcm: one sample per pass, so 6 passes, split into 3 parts of 2.
RENDER = ["cornell", "--integrator", "vcm", "--width", "16", "--height", "12", "--spp", "6", "--seed", "9"]

FAKE_SBATCH = textwrap.dedent('''\
    #!/usr/bin/env python3
    """Stand-in for sbatch: runs the job now (array tasks in turn) and prints its id."""
    import json, os, subprocess, sys
    from pathlib import Path
    state = Path(os.environ["FAKE_SLURM_STATE"])
    jobs_file = state / "jobs.json"
    jobs = json.loads(jobs_file.read_text()) if jobs_file.exists() else {}
    opts, args = {}, sys.argv[1:]
    while args and args[0].startswith("--"):
        key, _, value = args.pop(0)[2:].partition("=")
        opts[key] = value
    script, script_args = args[0], args[1:]
    job = str(1000 + len(jobs))
    export = opts.get("export", "ALL").split(",")
    env = dict(os.environ) if "ALL" in export else {"PATH": os.environ["PATH"]}
    env["FAKE_SLURM_STATE"] = str(state)
    env.update(item.split("=", 1) for item in export if "=" in item)
    tasks = [None]
    if "array" in opts:
        tasks = []
        for spec in opts["array"].split(","):
            first, _, last = spec.partition("-")
            tasks += range(int(first), int(last or first) + 1)
    depends = opts.get("dependency", "")
    pending = depends and any(jobs.get(d, {}).get("state") != "completed"
                              for d in depends.split(":", 1)[1].split(":"))
    codes = []
    if not pending:
        for task in tasks:
            task_env = dict(env, SLURM_JOB_ID=job)
            if task is not None:
                task_env.update(SLURM_ARRAY_JOB_ID=job, SLURM_ARRAY_TASK_ID=str(task),
                                SLURM_ARRAY_TASK_COUNT=str(len(tasks)))
            log = state / f"job-{job}-{task}.log"
            with open(log, "w") as out:
                codes.append(subprocess.run(["bash", script, *script_args], env=task_env,
                                            stdout=out, stderr=subprocess.STDOUT).returncode)
    jobs[job] = {"state": "pending" if pending else "completed" if not any(codes) else "failed",
                 "script": Path(script).name, "tasks": tasks}
    jobs_file.write_text(json.dumps(jobs))
    print(job if "parsable" in opts else f"Submitted batch job {job}")
    ''')

FAKE_SCANCEL = textwrap.dedent('''\
    #!/usr/bin/env python3
    """Stand-in for scancel: marks the jobs cancelled."""
    import json, os, sys
    from pathlib import Path
    jobs_file = Path(os.environ["FAKE_SLURM_STATE"]) / "jobs.json"
    jobs = json.loads(jobs_file.read_text())
    for job in sys.argv[1:]:
        if job not in jobs:
            sys.exit(f"scancel: error: Invalid job id {job} specified")
        jobs[job]["state"] = "cancelled"
    jobs_file.write_text(json.dumps(jobs))
    ''')


@pytest.fixture
def cluster(tmp_path: Path) -> dict[str, str]:
    """A PATH with the stand-in sbatch and scancel, and the folder of their job table."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name, text in (("sbatch", FAKE_SBATCH), ("scancel", FAKE_SCANCEL)):
        (bin_dir / name).write_text(text)
        (bin_dir / name).chmod(0o755)
    state = tmp_path / "slurm"
    state.mkdir()
    return {"PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}", "FAKE_SLURM_STATE": str(state)}


def jobs(cluster: dict[str, str]) -> dict[str, dict]:
    return json.loads((Path(cluster["FAKE_SLURM_STATE"]) / "jobs.json").read_text())


@pytest.fixture(scope="module")
def reference(pathtracer: Path, tmp_path_factory) -> bytes:
    out = tmp_path_factory.mktemp("one") / "one.pfm"
    subprocess.run([str(pathtracer), *RENDER, "--quiet", "-o", str(out)], check=True)
    return out.read_bytes()


def flaky(pathtracer: Path, folder: Path, part: int) -> Path:
    """A program that fails while folder/broken exists, for part `part` only."""
    wrapper = folder / "flaky-pathtracer"
    wrapper.write_text(
        "#!/bin/sh\n"
        f'case " $* " in *"part-{part:06d}.film"*) [ -e "{folder}/broken" ] && exit 3;; esac\n'
        f'exec "{pathtracer}" "$@"\n')
    wrapper.chmod(0o755)
    (folder / "broken").touch()
    return wrapper


def submit(cluster: dict[str, str], program: Path, parts_dir: Path, work: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, **cluster, PATHTRACER=str(program), PARTS=str(3), PARTS_DIR=str(parts_dir))
    return subprocess.run(["bash", str(SLURM / "submit.sh"), "out.pfm", *RENDER], env=env, cwd=work,
                          capture_output=True, text=True)


def test_job_array_and_merge_give_the_single_process_image(cluster, pathtracer, reference, tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    run = submit(cluster, pathtracer, tmp_path / "parts", work)
    assert run.returncode == 0, run.stderr
    assert "3 parts of 6 passes" in run.stdout
    assert [j["state"] for j in jobs(cluster).values()] == ["completed", "completed"]
    assert (work / "out.pfm").read_bytes() == reference


@pytest.mark.parametrize("failed", [0, 2])
def test_failed_task_is_rerun_alone_and_merged(cluster, pathtracer, reference, tmp_path, failed):
    work = tmp_path / "work"
    work.mkdir()
    parts_dir = tmp_path / "parts"
    program = flaky(pathtracer, tmp_path, failed)
    run = submit(cluster, program, parts_dir, work)
    assert run.returncode == 0, run.stderr
    render_job, merge_job = jobs(cluster)
    assert jobs(cluster)[render_job]["state"] == "failed"
    assert jobs(cluster)[merge_job]["state"] == "pending", "afterok on a failed array never runs"
    assert not (work / "out.pfm").exists()
    assert not (parts_dir / f"part-{failed:06d}.film").exists()

    (tmp_path / "broken").unlink()
    # From another folder and a shell without the submission's variables: PARTS_DIR is all.
    clean = {"PATH": cluster["PATH"], "FAKE_SLURM_STATE": cluster["FAKE_SLURM_STATE"], "HOME": str(tmp_path)}
    rerun = subprocess.run(["bash", str(SLURM / "rerun.sh"), str(parts_dir), str(failed)], env=clean,
                           cwd=tmp_path, capture_output=True, text=True)
    assert rerun.returncode == 0, rerun.stderr
    table = jobs(cluster)
    assert table[merge_job]["state"] == "cancelled", "the merge left waiting is cancelled"
    new_render, new_merge = list(table)[2:]
    assert table[new_render]["tasks"] == [failed]
    assert table[new_render]["state"] == "completed", \
        (Path(cluster["FAKE_SLURM_STATE"]) / f"job-{new_render}-{failed}.log").read_text()
    assert table[new_merge]["state"] == "completed"
    assert (parts_dir / "merge_job").read_text().strip() == new_merge
    assert (work / "out.pfm").read_bytes() == reference


def test_rerun_refuses_a_task_outside_the_split(cluster, pathtracer, tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    parts_dir = tmp_path / "parts"
    assert submit(cluster, pathtracer, parts_dir, work).returncode == 0
    rerun = subprocess.run(["bash", str(SLURM / "rerun.sh"), str(parts_dir), "3"],
                           env=dict(os.environ, **cluster), capture_output=True, text=True)
    assert rerun.returncode == 0, rerun.stderr  # submitted: the task itself refuses
    table = jobs(cluster)
    task_job = list(table)[2]
    assert table[task_job]["state"] == "failed"
    log = (Path(cluster["FAKE_SLURM_STATE"]) / f"job-{task_job}-3.log").read_text()
    assert "array task 3 is not a part of this render (0 to 2)" in log
