"""The least lift that keeps one set of oriented boxes clear of another (runtime/boxlift.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from oacdsl.runtime.boxlift import lift_to_clear, oriented_boxes, overlap_heights
from oacdsl.runtime.transforms import rot_axis

SIGNS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)


def box(centre: tuple[float, float, float], half: tuple[float, float, float] = (0.5, 0.5, 0.5),
        r: np.ndarray | None = None) -> np.ndarray:
    """Eight corners of a box, in the order of ``shapes.corners``."""
    r = np.eye(3) if r is None else r
    return (SIGNS * np.array(half)) @ r.T + np.array(centre)


def test_oriented_boxes_recovers_centre_axes_and_halves() -> None:
    r = rot_axis((0.0, 0.0, 1.0), 0.3)
    c, axes, half = oriented_boxes(np.vstack([box((1.0, 2.0, 3.0), (0.1, 0.2, 0.3), r), box((0, 0, 0))]))
    assert np.allclose(c[0], (1.0, 2.0, 3.0)) and np.allclose(half[0], (0.1, 0.2, 0.3))
    assert np.allclose(np.abs(axes[0] @ r), np.eye(3), atol=1e-9)


def test_a_box_on_another_rises_by_its_height_and_the_margin() -> None:
    assert lift_to_clear(box((0, 0, 0)), box((0, 0, 0))) == pytest.approx(1.0)
    assert lift_to_clear(box((0, 0, 0)), box((0, 0, 0)), margin_m=0.1) == pytest.approx(1.1)


def test_a_box_beside_another_needs_no_lift_where_its_column_would() -> None:
    # 1.2 apart: clear by 0.2, more than the margin 0.1, at the same height
    assert lift_to_clear(box((1.2, 0, 0)), box((0, 0, 0)), margin_m=0.1) == 0.0
    # 1.05 apart: within the margin, so over it
    assert lift_to_clear(box((1.05, 0, 0)), box((0, 0, 0)), margin_m=0.1) == pytest.approx(1.1)
    # a box above another is clear as it is
    assert lift_to_clear(box((0, 0, 2)), box((0, 0, 0))) == 0.0


def test_a_turned_box_clears_an_edge_exactly() -> None:
    # a cube turned 45 deg about y, its lower-left edge dipping over the other's top right edge:
    # clear once that edge passes (0.5, 0.5), i.e. a lift of 0.5 + 0.5 - (1.2 - 0.5 * sqrt 2)
    turned = box((1.2, 0, 0), r=rot_axis((0.0, 1.0, 0.0), math.pi / 4))
    assert lift_to_clear(turned, box((0, 0, 0))) == pytest.approx(1.0 - (1.2 - 0.5 * math.sqrt(2)))


def test_the_lift_starts_from_a_given_height_and_skips_every_overlap() -> None:
    # two boxes stacked with a 0.2 gap: starting inside the lower one's span, the lift goes past
    # both when the gap is too small for the moving box (height 1), and to the gap when it fits
    fixed = np.vstack([box((0, 0, 0)), box((0, 0, 1.7))])
    assert lift_to_clear(box((0, 0, 0)), fixed, from_m=0.5) == pytest.approx(2.7)
    small = box((0, 0, 0), (0.5, 0.5, 0.05))
    assert lift_to_clear(small, fixed, from_m=0.5) == pytest.approx(0.55)
    assert len(overlap_heights(small, np.zeros((0, 3)))) == 0
