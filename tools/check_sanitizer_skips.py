#!/usr/bin/env python3
"""Check .ci/sanitizer_skips.txt: does the rest of the sanitizer stage reach every line of src/
that the listed tests reach?

The sanitizer stage of .ci/run leaves the listed tests out to keep CI short. Line coverage is
the proxy for what that loses: no line of src/ goes unchecked while the other tests and the
stage's scene loop execute every line those tests execute, but the sanitizers then see only the
rest of the stage's data passing through those lines, not the listed tests' own. This measures
the lines with gcov in a coverage build:

    cmake -S . -B build-cov -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPT_NATIVE=OFF \\
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -DNDEBUG --coverage" -DCMAKE_EXE_LINKER_FLAGS=--coverage
    cmake --build build-cov --target pathtracer unit_tests
    python3 tools/check_sanitizer_skips.py build-cov

It runs the suite without the listed tests plus every built-in scene with each integrator (the
same renders as the stage's scene loop in .ci/run: change the two together), then the listed
tests alone, and prints each line of src/ that only the second run
reached, with the listed tests that reach it. Exit status 1 when there is such a line.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def listed_tests() -> list[str]:
    lines = (ROOT / ".ci" / "sanitizer_skips.txt").read_text().splitlines()
    return [line.strip() for line in lines if line.strip() and not line.startswith("#")]


def name_regex(names: list[str]) -> str:
    return "^(" + "|".join(re.escape(n) for n in names) + ")$"


def reset_counters(build: Path) -> None:
    for gcda in build.rglob("*.gcda"):
        gcda.unlink()


def reached_lines(build: Path) -> set[tuple[str, int]]:
    """(file relative to the repository, line) of src/ executed since the last reset."""
    src = str(ROOT / "src") + os.sep

    def one(gcda: Path) -> set[tuple[str, int]]:
        out = subprocess.run(["gcov", "--json-format", "--stdout", "-o", str(gcda.parent), str(gcda)],
                             capture_output=True, cwd=gcda.parent).stdout
        doc = json.loads(out) if out.strip() else {"files": []}
        lines = set()
        for f in doc["files"]:
            path = os.path.realpath(os.path.join(doc.get("current_working_directory", ""), f["file"]))
            if path.startswith(src):
                rel = os.path.relpath(path, ROOT)
                lines.update((rel, entry["line_number"]) for entry in f["lines"] if entry["count"] > 0)
        return lines

    with ThreadPoolExecutor(os.cpu_count() or 2) as pool:
        return set().union(*pool.map(one, list(build.rglob("*.gcda"))))


def ctest(build: Path, *selection: str) -> None:
    # A failing test still counts what it reached; the Release ctest is where failures matter.
    subprocess.run(["ctest", "--test-dir", str(build), "-j", "2", *selection], capture_output=True)


def scene_loop(build: Path) -> None:
    program = str(build / "pathtracer")
    scenes = subprocess.run([program, "--list-scenes"], capture_output=True, text=True, check=True).stdout
    jobs = [(scene.split()[0], integrator) for scene in scenes.splitlines() if scene.strip()
            for integrator in ("path", "bdpt", "vcm")]

    def render(job: tuple[str, str]) -> None:
        scene, integrator = job
        subprocess.run([program, scene, "--integrator", integrator, "--width", "32", "--height", "32", "--spp", "4",
                        "--quiet", "-o", str(build / f"skips-{scene}-{integrator}.pfm")], capture_output=True)

    with ThreadPoolExecutor(2) as pool:
        list(pool.map(render, jobs))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build", type=Path, help="a coverage build (see above)")
    build = parser.parse_args().build.resolve()
    skips = listed_tests()

    reset_counters(build)
    ctest(build, "-E", name_regex(skips))
    scene_loop(build)
    rest = reached_lines(build)
    reset_counters(build)
    ctest(build, "-R", name_regex(skips))
    only = reached_lines(build) - rest
    print(f"the rest of the stage reaches {len(rest)} lines of src/; the listed tests, {len(only)} more")
    if not only:
        return 0
    by_test = {}
    for name in skips:
        reset_counters(build)
        ctest(build, "-R", name_regex([name]))
        by_test[name] = reached_lines(build) & only
    for path, line in sorted(only):
        text = (ROOT / path).read_text().splitlines()[line - 1].strip()
        reaching = ", ".join(name for name, lines in by_test.items() if (path, line) in lines)
        print(f"{path}:{line}: {text}\n    reached by {reaching}")
    return 1


if __name__ == "__main__":
    sys.exit(main())
