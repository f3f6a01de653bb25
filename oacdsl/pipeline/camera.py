"""Pictures of the robot during the run: before it, at each step's change, and after each step.

:class:`StepCamera` renders offscreen (the runtime's :class:`~oacdsl.runtime.render.Renderer`,
no shadows, :data:`FRAME_SIZE`) from a free camera that looks at the table from its far
side. Besides the frame after every step it catches the *moment* of each step: it
observes the run at :data:`MOMENT_RATE_HZ` and renders once, the first time all of the
step's predicted (positive) effects hold in the simulation — the cup tilted while the
liquid lands in the bowl, the mixer touching the bowl's floor — which is the picture
the paper's Fig. 4 shows. Without a rendering backend it renders nothing and says why.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["FRAME_SIZE", "MOMENT_RATE_HZ", "VIEW", "StepCamera"]

#: Size of the rendered frames (width, height), pixels: small keeps software rendering fast.
FRAME_SIZE = (480, 360)
#: The view: look-at point (m), azimuth (deg), elevation (deg), distance (m); from the table's
#: far side, a little from the robot's left.
VIEW = ((0.5, 0.0, 0.98), 195.0, -28.0, 1.55)
#: How often the camera checks whether the current step's predicted effects hold, Hz.
MOMENT_RATE_HZ = 20.0


def _camera() -> Any:
    import mujoco

    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    (cam.lookat[0], cam.lookat[1], cam.lookat[2]), cam.azimuth, cam.elevation, cam.distance = VIEW
    return cam


class StepCamera:
    """Renders ``robot_00.png`` (before), ``robot_NN_moment.png`` and ``robot_NN.png`` into
    ``folder``; an observer of the control loop (add it with ``controller.add_observer``).

    ``steps`` are the run's bound primitive steps (:class:`oacdsl.runtime.binding.Step`).
    """

    rate_hz = MOMENT_RATE_HZ

    def __init__(self, model: Any, steps: Sequence[Any], folder: Path) -> None:
        from oacdsl.runtime.binding import bound_atoms
        from oacdsl.runtime.render import Renderer, RenderUnavailable

        self.folder = folder
        self.frames: dict[str, Path] = {}
        self.unavailable: str | None = None
        self.renderer: Any = None
        self._effects = [[a for a in bound_atoms(s.oac.effect, s.binding) if not a[2]] for s in steps]
        self._index = 0
        self._caught: set[int] = set()
        try:
            self.renderer = Renderer(model, FRAME_SIZE)
            self.renderer.camera = _camera()
        except RenderUnavailable as error:
            self.unavailable = str(error)

    def snapshot(self, name: str, world: Any) -> None:
        if self.renderer is None:
            return
        from oacdsl.runtime.render import write_png

        path = self.folder / f"{name}.png"
        write_png(path, self.renderer.render(world.data))
        self.frames[name] = path

    def __call__(self, world: Any) -> None:
        i = self._index
        if self.renderer is None or i >= len(self._effects) or i in self._caught or not self._effects[i]:
            return
        from oacdsl.runtime.binding import holds

        state = world.relations()
        if all(holds(state, a, b, n) for a, b, n in self._effects[i]):
            self._caught.add(i)
            self.snapshot(f"robot_{i + 1:02d}_moment", world)

    def step_done(self, index: int, world: Any) -> None:
        """Render the frame after step ``index`` (from 0) and watch for the next step's moment."""
        self.snapshot(f"robot_{index + 1:02d}", world)
        self._index = index + 1

    def close(self) -> None:
        if self.renderer is not None:
            self.renderer.close()
            self.renderer = None
