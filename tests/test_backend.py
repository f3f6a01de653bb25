"""MuJoCo's OpenGL backend is chosen in one place (oacdsl/cli/backend.py) for run and reproduce."""

from __future__ import annotations

import os
import sys

import pytest

import oacdsl.runtime.render as render
from oacdsl.cli.backend import MISSING, NONE_FOUND, prepare_backend


@pytest.fixture
def fresh(monkeypatch: pytest.MonkeyPatch) -> pytest.MonkeyPatch:
    """As before MuJoCo is imported, with MUJOCO_GL unset (both restored afterwards)."""
    monkeypatch.delitem(sys.modules, "mujoco", raising=False)
    monkeypatch.delenv("MUJOCO_GL", raising=False)
    return monkeypatch


def test_a_backend_whose_library_is_missing_is_disabled(fresh: pytest.MonkeyPatch):
    fresh.setenv("MUJOCO_GL", "osmesa")
    fresh.setattr(render, "backend_available", lambda name: name != "osmesa")
    assert prepare_backend(render=False) == MISSING.format("osmesa") == (
        "MUJOCO_GL=osmesa but its library is not installed"
    )
    assert os.environ["MUJOCO_GL"] == "disable"


def test_unset_it_becomes_the_first_offscreen_backend_when_pictures_are_wanted(fresh: pytest.MonkeyPatch):
    fresh.setattr(render, "choose_backend", lambda: "egl")
    assert prepare_backend(render=False) is None and "MUJOCO_GL" not in os.environ
    assert prepare_backend(render=True) is None and os.environ["MUJOCO_GL"] == "egl"
    fresh.delenv("MUJOCO_GL")
    fresh.setattr(render, "choose_backend", lambda: None)
    assert prepare_backend(render=True) == NONE_FOUND and "MUJOCO_GL" not in os.environ


def test_nothing_changes_once_mujoco_is_imported(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setitem(sys.modules, "mujoco", object())
    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    monkeypatch.setattr(render, "backend_available", lambda name: False)
    assert prepare_backend(render=True) is None
    assert os.environ["MUJOCO_GL"] == "osmesa"
