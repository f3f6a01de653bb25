"""Synthetic recordings with known shapes, for contacts from geometry (issue 20's cases).

Every object is a rigid body whose markers sit exactly where its :class:`ShapeModel` declares
them, posed along a path (origin = the centre of its base, a yaw about z), plus 0.2 mm of
jitter; a hand is five markers on the back of a flat hand 2 cm off the palm (wrist, knuckles,
finger tip). Positions in metres, 100 Hz, the table top at z = 0.9 m.
"""

from __future__ import annotations

import numpy as np
from _aas_helpers import path, recording

from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.shapes import Primitive, ShapeModel

RATE_HZ = 100.0
TABLE_Z = 0.9
_HAND = np.array([(-0.08, -0.03), (-0.08, 0.03), (0.0, -0.035), (0.0, 0.035), (0.07, 0.0)])  # (along, across)


def model(prims: list[tuple[str, tuple[float, float, float], tuple[float, float, float]]],
          markers: list[tuple[float, float, float]]) -> ShapeModel:
    return ShapeModel(tuple(Primitive(k, s, a) for k, s, a in prims), np.array(markers, dtype=float))


def rigid(shape: ShapeModel, origin: np.ndarray, yaw: np.ndarray | None = None) -> np.ndarray:
    """(F, k, 3) the declared markers of ``shape`` at ``origin`` (F, 3), turned by ``yaw`` (F,) rad."""
    yaw = np.zeros(len(origin)) if yaw is None else yaw
    c, s = np.cos(yaw), np.sin(yaw)
    m = shape.markers_m
    x = c[:, None] * m[None, :, 0] - s[:, None] * m[None, :, 1]
    y = s[:, None] * m[None, :, 0] + c[:, None] * m[None, :, 1]
    return np.stack([x, y, np.broadcast_to(m[:, 2], x.shape)], axis=-1) + origin[:, None, :]


def hand(palm: np.ndarray, normal: tuple[float, float, float], along: np.ndarray | tuple[float, float, float]
         ) -> np.ndarray:
    """(F, 5, 3) hand markers 2 cm off ``palm`` (F, 3) along ``normal``, the hand along ``along``."""
    n = np.asarray(normal, dtype=float)
    u = np.broadcast_to(np.asarray(along, dtype=float), palm.shape)
    w = np.cross(n, u)
    back = palm + 0.02 * n
    along_u = _HAND[None, :, 0, None] * u[:, None, :]
    return back[:, None, :] + along_u + _HAND[None, :, 1, None] * w[:, None, :]


def finish(tracks: dict[str, np.ndarray], seed: int = 0) -> Recording:
    rng = np.random.default_rng(seed)
    noisy = {k: v + rng.normal(0.0, 0.0002, v.shape) for k, v in tracks.items()}
    return recording(noisy, RATE_HZ, "synthetic")


def yaw_path(frames: int, keys: list[tuple[int, float]]) -> np.ndarray:
    return np.interp(np.arange(frames), [k for k, _ in keys], [v for _, v in keys])


BOARD = model([("box", (0.40, 0.20, 0.015), (0, 0, 0))],
              [(0.19, 0.09, 0.015), (-0.19, -0.09, 0.015), (-0.19, 0.09, 0.015), (0.05, -0.10, 0.005)])


def bottle_and_lid() -> tuple[Recording, dict[str, ShapeModel]]:
    """The left hand holds a still bottle low while the right hand turns its lid (markers near the top)."""
    f = 700
    bottle = model([("cylinder", (0.04, 0.20, 0), (0, 0, 0))],
                   [(0.04, 0, 0.17), (-0.04, 0, 0.15), (0, 0.04, 0.18), (0, -0.04, 0.13)])
    lid = model([("cylinder", (0.017, 0.025, 0), (0, 0, 0))],
                [(0.03, 0, 0.03), (-0.02, 0.02, 0.035), (0, -0.03, 0.025), (0, 0, 0.05)])
    b0 = np.array([0.5, 0.0, TABLE_Z])
    lid_at = np.tile(b0 + [0, 0, 0.20], (f, 1))
    turn = yaw_path(f, [(300, 0.0), (450, 1.5)])
    grip = b0 + [0, 0.04, 0.06]
    away = (0.5, 0.35, 0.95)
    left = path(f, [(100, away), (180, tuple(grip)), (550, tuple(grip)), (630, away)])
    top = tuple(b0 + [0, 0, 0.225])
    right = path(f, [(150, (0.5, -0.35, 1.0)), (250, top), (480, top), (560, (0.5, -0.35, 1.0))])
    along = np.stack([np.cos(turn), np.sin(turn), np.zeros(f)], axis=1)
    tracks = {
        "bottle": rigid(bottle, np.tile(b0, (f, 1))),
        "lid": rigid(lid, lid_at, turn),
        "left_hand": hand(left, (0, 1, 0), (1, 0, 0)),
        "right_hand": hand(right, (0, 0, 1), along),
    }
    return finish(tracks), {"bottle": bottle, "lid": lid}


def peeler_and_cucumber() -> tuple[Recording, dict[str, ShapeModel]]:
    """A peeler strokes the far end of a long cucumber whose markers sit at its other end; the
    cucumber lies on a board whose corner markers are nearer the peeler's than the cucumber's."""
    f = 700
    cucumber = model([("box", (0.36, 0.045, 0.045), (0, 0, 0))],
                     [(-0.17, 0, 0.045), (-0.13, 0, 0.045), (-0.15, 0.0225, 0.025), (-0.15, -0.0225, 0.015)])
    peeler = model([("box", (0.12, 0.025, 0.012), (0, 0, 0))],
                   [(-0.05, 0, 0.03), (-0.02, 0, 0.025), (-0.04, 0.015, 0.015), (-0.035, -0.015, 0.02)])
    board0 = np.array([0.5, 0.0, TABLE_Z])
    c0 = board0 + [0, 0, 0.015]
    top = c0[2] + 0.045
    rest = (0.5, -0.30, TABLE_Z)
    work = [(250 + 25 * i, (0.61 + (0.03 if i % 2 else -0.03), 0.0, top)) for i in range(11)]
    p_origin = path(f, [(150, rest), (240, (0.61, 0.0, top + 0.05)), *work,
                        (520, (0.61, 0.0, top + 0.05)), (580, rest)])
    right = path(f, [(60, (0.5, -0.55, 1.0)), (140, rest), (150, rest), (580, rest), (600, rest),
                     (660, (0.5, -0.55, 1.0))])
    t = np.arange(f)[:, None]
    right = np.where((t >= 140) & (t < 600), p_origin, right) + [-0.03, 0, 0.012]
    grip = tuple(c0 + [-0.15, 0, 0.045])
    left = path(f, [(50, (0.2, 0.3, 1.0)), (120, grip), (620, grip), (680, (0.2, 0.3, 1.0))])
    tracks = {
        "board": rigid(BOARD, np.tile(board0, (f, 1))),
        "cucumber": rigid(cucumber, np.tile(c0, (f, 1))),
        "peeler": rigid(peeler, p_origin),
        "left_hand": hand(left, (0, 0, 1), (1, 0, 0)),
        "right_hand": hand(right, (0, 0, 1), (1, 0, 0)),
    }
    return finish(tracks), {"board": BOARD, "cucumber": cucumber, "peeler": peeler}


def knife_on_board() -> tuple[Recording, dict[str, ShapeModel]]:
    """A knife lies on a board from the first frame to the last; the right hand lifts it, cuts in
    the air above the board and lays it down again a little further on."""
    f = 600
    knife = model([("box", (0.25, 0.025, 0.015), (0, 0, 0))],
                  [(-0.10, 0, 0.025), (-0.06, 0, 0.03), (-0.08, 0.012, 0.02), (-0.04, -0.01, 0.018)])
    board0 = np.array([0.5, 0.0, TABLE_Z])
    lying = (0.5, 0.02, TABLE_Z + 0.015)
    down = (0.53, 0.02, TABLE_Z + 0.015)
    up = [(280 + 20 * i, (0.5 + (0.03 if i % 2 else -0.03), 0.02, TABLE_Z + 0.075)) for i in range(7)]
    k_origin = path(f, [(220, lying), (270, (0.5, 0.02, TABLE_Z + 0.075)), *up, (460, down)])
    away = (0.5, -0.4, 1.05)
    right = path(f, [(100, away), (180, lying), (500, down), (560, away)])
    right = np.where((np.arange(f)[:, None] >= 180) & (np.arange(f)[:, None] < 500), k_origin, right)
    right = right + [-0.07, 0, 0.015]
    tracks = {
        "board": rigid(BOARD, np.tile(board0, (f, 1))),
        "knife": rigid(knife, k_origin),
        "right_hand": hand(right, (0, 0, 1), (1, 0, 0)),
        "left_hand": hand(np.tile([0.5, 0.5, 1.0], (f, 1)), (0, 0, 1), (1, 0, 0)),
    }
    return finish(tracks), {"board": BOARD, "knife": knife}


def spoon_in_bowl() -> tuple[Recording, dict[str, ShapeModel]]:
    """The right hand stirs a spoon in a bowl; the spoon's markers sit high on its handle, about
    140 mm from the bowl's rim markers."""
    f = 700
    bowl = model([("cylinder", (0.10, 0.08, 0), (0, 0, 0))],
                 [(0.10, 0, 0.08), (-0.10, 0, 0.08), (0, 0.10, 0.08), (0, -0.10, 0.0)])
    spoon = model([("cylinder", (0.025, 0.01, 0), (0, 0, 0)), ("cylinder", (0.006, 0.24, 0), (0, 0, 0.01))],
                  [(0.02, 0, 0.25), (-0.015, 0.01, 0.22), (0, -0.02, 0.24), (0, 0, 0.20)])
    b0 = np.array([0.5, 0.0, TABLE_Z])
    rest = np.array([0.5, -0.3, TABLE_Z])
    t = np.arange(f)
    phase = 2 * np.pi * (t - 250) / 80
    stir = np.stack([0.5 + 0.03 * np.cos(phase), 0.03 * np.sin(phase), np.full(f, TABLE_Z + 0.01)], axis=1)
    above, inside = (0.53, 0.0, TABLE_Z + 0.12), (0.53, 0.0, TABLE_Z + 0.01)
    s_origin = path(f, [(150, tuple(rest)), (240, above), (250, inside), (500, inside), (510, above),
                        (580, tuple(rest))])
    s_origin = np.where(((t >= 250) & (t < 500))[:, None], stir, s_origin)
    away = (0.3, -0.5, 1.1)
    grip = np.array([-0.008, 0, 0.21])
    right = path(f, [(60, away), (140, tuple(rest + grip)), (600, tuple(rest + grip)), (660, away)])
    right = np.where(((t >= 140) & (t < 600))[:, None], s_origin + grip, right)
    tracks = {
        "bowl": rigid(bowl, np.tile(b0, (f, 1))),
        "spoon": rigid(spoon, s_origin),
        "right_hand": hand(right, (-1, 0, 0), (0, 0, 1)),
        "left_hand": hand(np.tile([0.3, 0.4, 1.0], (f, 1)), (0, 0, 1), (1, 0, 0)),
    }
    return finish(tracks), {"bowl": bowl, "spoon": spoon}
