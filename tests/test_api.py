"""The Python API (docs/api.md): its worked example runs as written; same errors as the CLI."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import oacdsl

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "api.md").read_text(encoding="utf-8"), re.S)


def test_the_worked_example_runs_as_written(monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    scope: dict[str, object] = {}
    exec(compile(BLOCKS[0], "docs/api.md", "exec"), scope)  # noqa: S102  (the documentation's own code)
    out = capsys.readouterr().out
    assert "kitchen 100.0 Hz" in out
    assert "['grasp', 'pour', 'place', 'grasp', 'pour', 'place', 'grasp', 'mix']" in out
    assert "no_such_file.c3d: no such recording file" in out
    assert "oac dough_again(" in scope["composed"].text  # type: ignore[attr-defined]


@pytest.mark.slow
def test_the_robot_block_runs_as_written(monkeypatch):
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    monkeypatch.chdir(ROOT)
    scope: dict[str, object] = {}
    exec(compile(BLOCKS[0] + BLOCKS[1], "docs/api.md", "exec"), scope)  # noqa: S102
    assert scope["result"].success, scope["result"].error  # type: ignore[attr-defined]


def test_public_names_are_all_there_and_import_oacdsl_stays_light():
    for name in oacdsl.__all__:
        assert getattr(oacdsl, name) is not None
    with pytest.raises(AttributeError, match="has no attribute 'nope'"):
        oacdsl.nope  # noqa: B018
    code = "import sys, oacdsl; print(any(m.startswith(('oacdsl.pipeline', 'numpy')) for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_errors_are_the_command_lines(tmp_path):
    bad = tmp_path / "bad.oac"
    bad.write_text("class {\n", encoding="utf-8")
    with pytest.raises(oacdsl.LanguageError, match=r"bad\.oac:1:7"):
        oacdsl.load_library(bad)
    with pytest.raises(oacdsl.UsageError, match="segment: .*unexpected keyword argument 'nope'"):
        oacdsl.segment(oacdsl.read_recording(ROOT / "data" / "dough.c3d"), nope=1)
    demo = oacdsl.load_demonstration(ROOT / "data" / "dough.c3d", ROOT / "library")
    with pytest.raises(oacdsl.UsageError, match="name '1x'"):
        oacdsl.compose(demo, "1x")


def test_compose_writes_only_when_asked(tmp_path):
    demo = oacdsl.load_demonstration(ROOT / "data" / "dough.c3d", ROOT / "library")
    composed = oacdsl.compose(demo, "dough_api")
    assert composed.path is None and not list(tmp_path.iterdir())
    target = tmp_path / "dough_api.oac"
    written = oacdsl.compose(demo, "dough_api", write_to=target)
    assert written.path == target and target.read_text(encoding="utf-8") == written.text
    assert oacdsl.load_library(ROOT / "library", target).oacs["dough_api"].composed


def test_mine_is_a_function_at_the_top_level():
    from oacdsl.mining.engine import mine

    assert oacdsl.mine is mine
