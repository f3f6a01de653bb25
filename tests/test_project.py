"""Project hygiene: CI runs the README's test command, the CLI never shows a traceback."""

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def readme_test_command() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    match = re.search(r"<!-- test-command -->\s*```(?:sh|bash)?\n(.+?)\n```", text, re.S)
    assert match, "README.md lacks the test command block"
    return match.group(1).strip()


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert readme_test_command() in ci.splitlines()


def test_oacc_help_and_version():
    out = subprocess.run([sys.executable, "-m", "oacdsl", "--help"], capture_output=True, text=True)
    assert out.returncode == 0 and "usage: oacc" in out.stdout
    out = subprocess.run([sys.executable, "-m", "oacdsl", "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.startswith("oacc ")


def test_unknown_command_is_a_usage_error():
    out = subprocess.run([sys.executable, "-m", "oacdsl", "frobnicate"], capture_output=True, text=True)
    assert out.returncode == 2 and "Traceback" not in out.stderr and "invalid choice" in out.stderr


def test_skills_command_lists_runtime_skills():
    out = subprocess.run([sys.executable, "-m", "oacdsl", "skills"], capture_output=True, text=True)
    assert out.returncode == 0 and "reach_and_grasp" in out.stdout
