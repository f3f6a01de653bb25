"""Writing a recording as KIT MMM XML (markers only), which :func:`~.mmm.read_mmm` reads back.

One ``<Motion name="true_GROUP" type="object">`` per marker group (the reader drops the
``true_`` prefix again, so the groups come back under their names), holding a
``MoCapMarker`` sensor with one ``Measurement`` per frame (``timestep`` in seconds) and a
``MarkerPosition`` per marker in millimetres. A marker's ``GROUP:`` prefix is left out (the
reader puts it back where two motions share a name). A gap is left out of its measurement,
as in the KIT files; a measurement that would be empty, and a marker that is a gap in every
frame, is written ``nan nan nan`` once so that no frame or marker is lost. Other sensors
(``ModelPose``, ``Kinematic``) are not written. The file is written to a temporary path
and renamed (:mod:`oacdsl.atomic`).
"""

from __future__ import annotations

import io
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from oacdsl.atomic import write_atomic
from oacdsl.errors import RecordingError
from oacdsl.segmentation.recording import Recording

__all__ = ["write_mmm"]


def _groups_for_writing(rec: Recording) -> list[tuple[str, tuple[int, ...]]]:
    owner: dict[int, str] = {}
    for group, idx in rec.groups.items():
        for i in idx:
            if i in owner:
                raise RecordingError(
                    f"cannot write MMM: marker {rec.marker_names[i]!r} is in groups"
                    f" {owner[i]!r} and {group!r}",
                    location=rec.source,
                )
            owner[i] = group
    loose = [n for i, n in enumerate(rec.marker_names) if i not in owner]
    if loose:
        shown = ", ".join(loose[:5]) + (", …" if len(loose) > 5 else "")
        raise RecordingError(
            f"cannot write MMM: {len(loose)} markers belong to no group ({shown}); an MMM file holds"
            " markers by motion (write a .c3d, or group them)",
            location=rec.source,
        )
    return list(rec.groups.items())


def _timestep(t: float) -> str:
    text = f"{t:.6f}".rstrip("0").rstrip(".")
    return text or "0"


def _xyz(v: np.ndarray) -> str:
    return " ".join(f"{c:.9g}" for c in v)


def write_mmm(recording: Recording, path: str | Path, name: str | None = None) -> Path:
    """Write ``recording``'s grouped markers as an MMM XML file at ``path``, atomically."""
    path = Path(path)
    groups = _groups_for_writing(recording)
    mm = recording.positions_m * 1000.0
    finite = np.all(np.isfinite(mm), axis=-1)  # (F, M)
    out = io.StringIO()
    doc = name or path.name.split(".")[0]
    out.write(f'<?xml version="1.0" encoding="UTF-8"?>\n<MMM version="2.0" name={quoteattr(doc)}>\n')
    for group, idx in groups:
        labels = [recording.marker_names[i].removeprefix(f"{group}:") for i in idx]
        never = {k for k, i in enumerate(idx) if not finite[:, i].any()}
        out.write(f'\t<Motion name={quoteattr("true_" + group)} type="object" synchronized="true">\n')
        out.write(
            '\t\t<Sensors>\n\t\t\t<Sensor type="MoCapMarker" version="1.0">\n'
            "\t\t\t\t<Configuration/>\n\t\t\t\t<Data>\n"
        )
        for f, t in enumerate(recording.times_s):
            out.write(f'\t\t\t\t\t<Measurement timestep="{_timestep(float(t))}">\n')
            written = 0
            for k, i in enumerate(idx):
                if finite[f, i]:
                    text = _xyz(mm[f, i])
                elif (f == 0 and k in never) or (written == 0 and k == len(idx) - 1):
                    text = "nan nan nan"
                else:
                    continue
                written += 1
                out.write(
                    f"\t\t\t\t\t\t<MarkerPosition name={quoteattr(labels[k])}>{text}</MarkerPosition>\n"
                )
            out.write("\t\t\t\t\t</Measurement>\n")
        out.write("\t\t\t\t</Data>\n\t\t\t</Sensor>\n\t\t</Sensors>\n\t</Motion>\n")
    out.write("</MMM>\n")
    try:
        return write_atomic(path, out.getvalue())
    except OSError as err:
        raise RecordingError(f"cannot write: {err.strerror or err}", location=str(path)) from None
