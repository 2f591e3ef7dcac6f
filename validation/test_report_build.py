"""docs/report/build_report.py's run logic, with stand-in sections (no renders, ~1 s): a failed
stage does not stop the others, `--only` re-runs one section and takes the others from their
cached results, `--only` without cached results is an error, and the per-stage times reach
results.json. (The real sections are exercised by `build_report.py --quick` in CI.)"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import pytest

REPORT_DIR = Path(__file__).resolve().parent.parent / "docs" / "report"


@pytest.fixture()
def report(monkeypatch, tmp_path):
    """build_report with sections a, b, c (b fails until told otherwise) and a template naming
    one number of each."""
    monkeypatch.syspath_prepend(str(REPORT_DIR))
    module = importlib.import_module("build_report")
    calls = {"a": 0, "b": 0, "c": 0}
    state = {"b_fails": True}

    def section(name):
        def run(r, p, figs):
            calls[name] += 1
            if name == "b" and state["b_fails"]:
                raise RuntimeError("planted failure")
            return {"x": f"{name}-value"}
        return run

    monkeypatch.setattr(module, "SECTIONS", {n: section(n) for n in calls})
    template_dir = tmp_path / "template"
    template_dir.mkdir()
    (template_dir / "report.md.in").write_text("{{a.x}} {{b.x}} {{c.x}} {{run.stage_list}}\n")
    monkeypatch.setattr(module, "REPORT_DIR", template_dir)
    return module, calls, state


def run(module, tmp_path, pathtracer, *extra):
    return module.main(["--quick", "--program", str(pathtracer), "--out", str(tmp_path / "out"),
                        "--cache-dir", str(tmp_path / "cache"), *extra])


def test_failed_stage_then_only(report, tmp_path, pathtracer, capsys):
    module, calls, state = report
    assert run(module, tmp_path, pathtracer) == 1  # b failed: no report, but a and c ran
    assert calls == {"a": 1, "b": 1, "c": 1}
    assert "failed stage(s): b" in capsys.readouterr().out
    assert not (tmp_path / "out" / "README.md").exists()

    state["b_fails"] = False
    assert run(module, tmp_path, pathtracer, "--only", "b") == 0
    assert calls == {"a": 1, "b": 2, "c": 1}  # a and c from their cached results
    text = (tmp_path / "out" / "README.md").read_text()
    assert text.startswith("a-value b-value c-value ")
    results = json.loads((tmp_path / "out" / "results.json").read_text())
    assert set(results["run"]["stage_seconds"]) == {"a", "b", "c"}


def test_only_without_cached_results_is_an_error(report, tmp_path, pathtracer):
    module, calls, _ = report
    with pytest.raises(SystemExit, match="no cached results of section 'a'"):
        run(module, tmp_path, pathtracer, "--only", "b")


def test_changed_settings_do_not_reuse_cached_results(report, tmp_path, pathtracer, monkeypatch):
    module, calls, state = report
    state["b_fails"] = False
    assert run(module, tmp_path, pathtracer) == 0
    monkeypatch.setitem(module.QUICK, "size", module.QUICK["size"] + 1)
    with pytest.raises(SystemExit, match="no cached results"):
        run(module, tmp_path, pathtracer, "--only", "b")


def test_from_results_takes_the_other_sections_from_an_earlier_run(report, tmp_path, pathtracer, monkeypatch):
    """--only b --from-results FILE on a fresh cache: a and c come from FILE (not re-run), and the
    run's provenance names them and FILE's commit; without --only, --from-results is refused."""
    module, calls, state = report
    state["b_fails"] = False
    assert run(module, tmp_path, pathtracer) == 0
    earlier = tmp_path / "earlier.json"
    data = json.loads((tmp_path / "out" / "results.json").read_text())
    data["a"]["x"], data["run"]["commit"] = "a-earlier", "0123abcd"
    earlier.write_text(json.dumps(data))
    fresh = ["--quick", "--program", str(pathtracer), "--out", str(tmp_path / "out"),
             "--cache-dir", str(tmp_path / "fresh-cache")]
    assert module.main(fresh + ["--only", "b", "--from-results", str(earlier)]) == 0
    assert calls == {"a": 1, "b": 2, "c": 1}
    results = json.loads((tmp_path / "out" / "results.json").read_text())
    assert results["a"]["x"] == "a-earlier" and results["run"]["earlier_sections"] == ["a", "c"]
    assert "0123abcd" in results["run"]["provenance"] and "a, c" in results["run"]["provenance"]
    with pytest.raises(SystemExit):
        module.main(fresh + ["--from-results", str(earlier)])


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
