"""Shared pytest helpers for the validation suite.

Fixtures:

* ``repo_root``   -- pathlib.Path of the repository root.
* ``spectra_dir`` -- ``<repo>/spectra``.
* ``pathtracer_path`` -- path of the built renderer, from ``$SPT_PATHTRACER``
  or ``<repo>/build/pathtracer``; not checked for existence.
* ``pathtracer``  -- the same path; the test fails when the program is not
  built (a missing build must not pass silently).

The plain functions ``repo_root_path()`` and ``pathtracer_location()`` do the
same for code outside fixtures (helper modules, scripts).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import pytest

# colour-science warns at import time when SciPy is missing; the validation
# suite only uses parts of colour that do not need SciPy.
_SCIPY_WARNING = '"SciPy" related API'
warnings.filterwarnings("ignore", message=_SCIPY_WARNING)


def pytest_configure(config: pytest.Config) -> None:
    # pytest resets warning filters around collection and each test, so the
    # filter above must also be registered as an ini-style filter.
    config.addinivalue_line("filterwarnings", f"ignore:{_SCIPY_WARNING}")

_REPO_ROOT = Path(__file__).resolve().parent.parent


def repo_root_path() -> Path:
    """Repository root (the parent of ``validation/``)."""
    return _REPO_ROOT


def pathtracer_location() -> Path:
    """``$SPT_PATHTRACER`` if set (relative to the cwd), else ``<repo>/build/pathtracer``."""
    env = os.environ.get("SPT_PATHTRACER")
    if env:
        return Path(env).expanduser().resolve()
    return _REPO_ROOT / "build" / "pathtracer"


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return repo_root_path()


@pytest.fixture(scope="session")
def spectra_dir(repo_root: Path) -> Path:
    return repo_root / "spectra"


@pytest.fixture(scope="session")
def pathtracer_path() -> Path:
    return pathtracer_location()


@pytest.fixture(scope="session")
def pathtracer(pathtracer_path: Path) -> Path:
    if pathtracer_path.is_file() and os.access(pathtracer_path, os.X_OK):
        return pathtracer_path
    message = (
        f"renderer not found or not executable at {pathtracer_path} "
        "(build it, or set SPT_PATHTRACER)"
    )
    # A missing build must never pass silently: fail, do not skip.
    pytest.fail(message)
