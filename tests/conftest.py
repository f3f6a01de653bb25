"""Test-wide settings.

Hypothesis' per-example deadline is off: CI machines have 2 cores shared by two
pytest workers, so wall-clock time per example is noise, not a property of the code.
Performance is measured by the scripts in benchmarks/, not by tests.
"""

import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# the segmentation's evaluation oracles (KIT scoring, per-frame references) live in
# benchmarks/segeval, outside the installed package
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

settings.register_profile(
    "oacdsl", deadline=None, suppress_health_check=[HealthCheck.too_slow], print_blob=True
)
settings.load_profile("oacdsl")


@pytest.fixture(autouse=True)
def _private_run_store(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    """Runs a test makes without ``--db`` (``oacc run`` records by default) go to a store of
    its own, never the user's ``~/.local/share/oacdsl/runs.sqlite3``; subprocesses inherit it."""
    monkeypatch.setenv("OACDSL_DB", str(tmp_path_factory.mktemp("store") / "runs.sqlite3"))
