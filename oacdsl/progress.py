"""Progress of long multi-stage work on stderr: ``[2/5] match … done in 0.4 s``.

On a terminal a stage's line is written when it starts and completed in place (with optional
notes such as ``step 3/8`` updating it); when stderr is not a terminal (a log file, CI) each
stage prints one plain line when it ends; with ``quiet`` nothing is printed. Either way the
stages are recorded with their status and duration (:meth:`Progress.records`, the shape of
``result.json``'s ``stages``).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import IO, Any

__all__ = ["Progress", "StageRecord", "format_duration"]

_CLEAR = "\r\x1b[K"


def _isatty(stream: IO[str]) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, OSError, ValueError):
        return False


def format_duration(seconds: float) -> str:
    """``0.42 s``, ``12.3 s``, ``2 min 05 s``."""
    if seconds < 10:
        return f"{seconds:.2f} s" if seconds < 1 else f"{seconds:.1f} s"
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, rest = divmod(int(round(seconds)), 60)
    return f"{minutes} min {rest:02d} s"


@dataclass
class StageRecord:
    """One stage: ``status`` is ok, failed or skipped; ``duration_s`` in seconds of wall
    clock, ``cpu_s`` in seconds of this process's CPU time (user + system) in the stage."""

    name: str
    status: str
    duration_s: float | None = None
    detail: str | None = None
    cpu_s: float | None = None

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "status": self.status,
            "duration_s": self.duration_s,
            "cpu_s": self.cpu_s,
            "detail": self.detail,
        }


class Progress:
    """Stage-by-stage progress on ``stream`` (default ``sys.stderr``).

    ``stages`` is the planned list of stage names (or just their number) for the ``[i/n]``
    counter. ``clock`` returns wall seconds, ``cpu_clock`` the process's CPU seconds (both
    injectable for tests).
    """

    def __init__(
        self,
        stages: Sequence[str] | int,
        *,
        stream: IO[str] | None = None,
        quiet: bool = False,
        clock: Callable[[], float] = time.perf_counter,
        cpu_clock: Callable[[], float] = time.process_time,
    ) -> None:
        self.total = stages if isinstance(stages, int) else len(stages)
        self.stream = stream if stream is not None else sys.stderr
        self.quiet = quiet
        self.clock = clock
        self.cpu_clock = cpu_clock
        self.live = not quiet and _isatty(self.stream)
        self._records: list[StageRecord] = []
        self._current: str | None = None
        self._prefix = ""

    # -- output -------------------------------------------------------------------------------------
    def _write(self, text: str) -> None:
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):  # a closed or broken stderr must not break the work
            pass

    def _counter(self) -> str:
        n = len(self._records) + 1
        return f"[{n}/{max(self.total, n)}]"

    def _end(self, line: str) -> None:
        if self.quiet:
            return
        self._write((_CLEAR if self.live else "") + line + "\n")

    # -- stages -------------------------------------------------------------------------------------
    @contextmanager
    def stage(self, name: str) -> Iterator[Progress]:
        """Time the block as stage ``name``; an exception marks it failed and propagates."""
        if self._current is not None:
            raise RuntimeError(f"stage {name!r} started inside stage {self._current!r}")
        self._current, self._prefix = name, f"{self._counter()} {name}"
        if self.live:
            self._write(f"{self._prefix} …")
        start, cpu = self.clock(), self.cpu_clock()
        try:
            yield self
        except BaseException as error:
            took = self.clock() - start
            reason = str(error).splitlines()[0] if str(error) else type(error).__name__
            self._records.append(StageRecord(name, "failed", took, reason, self.cpu_clock() - cpu))
            self._end(f"{self._prefix} failed after {format_duration(took)}")
            raise
        finally:
            self._current = None
        took = self.clock() - start
        self._records.append(StageRecord(name, "ok", took, cpu_s=self.cpu_clock() - cpu))
        self._end(f"{self._prefix} done in {format_duration(took)}")

    def note(self, text: str) -> None:
        """Show what the current stage is doing (terminal only: updates the stage's line)."""
        if self.live and self._current is not None:
            self._write(f"{_CLEAR}{self._prefix} … {text}")

    def skip(self, name: str, reason: str) -> None:
        """Record stage ``name`` as skipped, with the reason."""
        self._end(f"{self._counter()} {name} skipped: {reason}")
        self._records.append(StageRecord(name, "skipped", None, reason))

    def records(self) -> list[dict[str, Any]]:
        """The stages so far, as ``result.json``'s ``stages`` list."""
        return [r.to_json() for r in self._records]

    @property
    def elapsed_s(self) -> float:
        """Total time of the recorded stages, seconds."""
        return sum(r.duration_s or 0.0 for r in self._records)
