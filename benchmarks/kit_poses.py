"""Object poses on the KIT development clips: the rigid fit of the markers against the MMM ``ModelPose``.

Accuracy, not speed. For each object of each development clip (Pour, Stir, Mix,
Wipe, Scoop, Cut — never the evaluation clips) the poses from
``oacdsl.segmentation.poses.fit_poses`` are compared with the file's ``ModelPose``
(``readers.mmm_pose.read_model_poses``) by ``poses.agreement``: the distance between
the fitted origin and the one ``ModelPose`` predicts, and the angle between the two
orientations (the constant offset between the frames taken at the fit's reference
frame); plus the fit's own RMS residual. Then the demonstrated motion of each clip's
sub-actions (``oacc segment CLIP --motion``) in one line per sub-action with a target.

    python benchmarks/kit_poses.py [--data FOLDER]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from oacdsl.segmentation import segment  # noqa: E402
from oacdsl.segmentation.grouping import recognise_preset  # noqa: E402
from oacdsl.segmentation.motion import sub_action_motions  # noqa: E402
from oacdsl.segmentation.poses import agreement, fit_poses  # noqa: E402
from oacdsl.segmentation.readers import read_recording  # noqa: E402
from oacdsl.segmentation.readers.mmm_pose import read_model_poses  # noqa: E402

DEVELOPMENT = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")


def data_folder(given: str | None) -> Path:
    if given:
        return Path(given)
    for shared in (ROOT.parent / "shared", ROOT.parents[1] / "shared"):
        if (shared / "mocap" / "kit_bimanual").is_dir():
            return shared / "mocap" / "kit_bimanual"
    sys.exit("kit_bimanual data not found next to the repository; pass --data FOLDER")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", metavar="FOLDER", help="the kit_bimanual folder")
    folder = data_folder(parser.parse_args().data)
    print(f"{'clip':<6} {'object':<22} {'residual':>9} {'position max':>13} {'angle median':>13}"
          f" {'angle max':>10}")
    motions = []
    for action in DEVELOPMENT:
        found = sorted(folder.glob(f"{action}_*.mmm.xml"))
        if len(found) != 1:
            sys.exit(f"expected one {action}_*.mmm.xml in {folder}, found {len(found)}")
        recording = read_recording(found[0])
        model = read_model_poses(found[0])
        for name, poses in fit_poses(recording).items():
            if name not in model or name.startswith("subject_"):
                continue
            position, angle = agreement(poses, model[name].T_world_model)
            print(f"{action:<6} {name:<22} {np.nanmedian(poses.residual_m) * 1e3:>7.2f}mm"
                  f" {np.nanmax(position) * 1e3:>11.2f}mm {math.degrees(np.nanmedian(angle)):>12.2f}°"
                  f" {math.degrees(np.nanmax(angle)):>9.2f}°")
        grouped, _ = recognise_preset(recording)
        motions += [(action, m) for m in sub_action_motions(grouped, segment(grouped)) if m.target]
    print(f"\n{'clip':<6} {'#':>2} {'moved':<20} {'target':<20} {'relation':<8} {'period':>7} {'cycles':>6}"
          f" {'radius':>7} {'tilt':>5} {'tilt time':>9}")
    for action, m in motions:
        f = m.features
        if f is None:
            continue
        period = f"{f.period_s:.2f}s" if f.period_s else "-"
        cycles = f"{f.cycles:.1f}" if f.cycles else "-"
        print(f"{action:<6} {m.index:>2} {m.moved:<20} {m.target:<20} {m.relation or '-':<8} {period:>7}"
              f" {cycles:>6} {f.radius_m * 1e3:>5.0f}mm {math.degrees(f.tilt_max_rad):>4.0f}°"
              f" {f.tilt_time_s:>8.1f}s")


if __name__ == "__main__":
    main()
