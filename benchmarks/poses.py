"""Rigid-fit throughput: the batched Kabsch fit of ``oacdsl.segmentation.poses`` against a per-frame loop.

Data (generated here): one 4-marker body tumbling along a path at 100 Hz for
``--minutes`` (default 10: 60,000 frames), 0.5 mm marker noise, 2 % of markers lost.

- ours: ``fit_constellation`` on every frame at once (one batched 3×3 SVD);
- baseline: the same least-squares fit written frame by frame (``np.linalg.svd`` of
  one 3×3 matrix per frame, visible markers only), timed on a slice and extrapolated.

Prints the medians of ``--repeats`` interleaved runs (CPU seconds of this process),
the ratio, and whether both agree on the slice (poses within 1e-9). No target is set
by an issue; the point is that pose fitting costs nothing next to segmentation:

    python benchmarks/poses.py
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from oacdsl.segmentation.poses import MIN_MARKERS, fit_constellation  # noqa: E402

RATE_HZ = 100.0


def data(frames: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    body = np.array([[0.04, 0.0, 0.0], [-0.03, 0.03, 0.01], [0.0, -0.05, 0.02], [-0.01, 0.02, -0.03]])
    body -= body.mean(axis=0)
    t = np.arange(frames) / RATE_HZ
    a, b = 0.7 * t, 0.4 * np.sin(t)
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    rot = np.zeros((frames, 3, 3))  # Rz(a) · Rx(b)
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 0, 2] = ca, -sa * cb, sa * sb
    rot[:, 1, 0], rot[:, 1, 1], rot[:, 1, 2] = sa, ca * cb, -ca * sb
    rot[:, 2, 1], rot[:, 2, 2] = sb, cb
    pts = np.einsum("fij,kj->fki", rot, body) + np.stack([0.1 * t, np.sin(t), 0 * t + 0.8], axis=1)[:, None]
    pts += rng.normal(0.0, 0.0005, pts.shape)
    pts[rng.random(pts.shape[:2]) < 0.02] = np.nan
    return body, pts


def per_frame(constellation: np.ndarray, pts: np.ndarray) -> np.ndarray:
    out = np.full((len(pts), 4, 4), np.nan)
    for f in range(len(pts)):
        seen = np.isfinite(pts[f]).all(axis=1)
        if seen.sum() < MIN_MARKERS:
            continue
        a, b = constellation[seen], pts[f, seen]
        ca, cb = a.mean(axis=0), b.mean(axis=0)
        u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
        d = np.sign(np.linalg.det(vt.T @ u.T))
        rot = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
        out[f] = np.eye(4)
        out[f, :3, :3], out[f, :3, 3] = rot, cb - rot @ ca
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--slice", type=int, default=3000, help="frames the per-frame loop is timed on")
    args = parser.parse_args()
    frames = int(args.minutes * 60 * RATE_HZ)
    body, pts = data(frames)
    part = pts[: args.slice]
    ours, loop = [], []
    for _ in range(args.repeats):
        t0 = time.process_time()
        fit_constellation(body, pts)
        ours.append(time.process_time() - t0)
        t0 = time.process_time()
        per_frame(body, part)
        loop.append((time.process_time() - t0) * frames / len(part))
    fast, _ = fit_constellation(body, part)
    slow = per_frame(body, part)
    agree = bool(np.allclose(np.nan_to_num(fast, nan=7.0), np.nan_to_num(slow, nan=7.0), atol=1e-9))
    m_ours, m_loop = statistics.median(ours), statistics.median(loop)
    print(f"{frames} frames ({args.minutes:g} min at {RATE_HZ:g} Hz), 4 markers, 2 % lost")
    print(f"batched fit:     {m_ours:8.3f} s  ({frames / m_ours:,.0f} frames/s)")
    print(f"per-frame loop:  {m_loop:8.3f} s  (extrapolated from {len(part)} frames)")
    print(f"ratio:           {m_loop / m_ours:8.1f}x")
    print(f"agree on the slice: {agree}")


if __name__ == "__main__":
    main()
