"""Offscreen rendering: MP4 video, PNG frames, one PNG of the current state, a live viewer.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when it is imported. This module
never changes the environment itself; the command line calls :func:`choose_backend`
*before* importing MuJoCo (``MUJOCO_GL`` if set, else EGL, else OSMesa). When no
backend works, :class:`RenderUnavailable` says so in one line and the run goes on
without pictures. Shadows and reflections are off (they dominate software-rendering
cost); ``mj_forward`` runs before the first frame; renderers are closed explicitly.
"""

from __future__ import annotations

import ctypes.util
import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.atomic import atomic_path
from oacdsl.errors import OacError

__all__ = [
    "RenderUnavailable",
    "choose_backend",
    "Renderer",
    "VideoRecorder",
    "render_png",
    "Viewer",
    "FRAME_SIZE",
    "backend_available",
    "write_png",
]

#: Default frame size (width, height), pixels.
FRAME_SIZE = (640, 480)


class RenderUnavailable(OacError):
    """No offscreen OpenGL backend could be used (the run itself is not affected)."""


_LIBRARIES = {"egl": "EGL", "osmesa": "OSMesa"}


def backend_available(name: str) -> bool:
    """Whether the shared library an offscreen backend needs is installed (glfw: assumed)."""
    lib = _LIBRARIES.get(name.lower())
    return lib is None or ctypes.util.find_library(lib) is not None


def choose_backend(environ: dict[str, str] | None = None) -> str | None:
    """The backend to use: ``MUJOCO_GL`` when set, else ``egl`` when libEGL is present,
    else ``osmesa`` when libOSMesa is present, else None. Reads, never writes, ``environ``."""
    env = os.environ if environ is None else environ
    if env.get("MUJOCO_GL"):
        return env["MUJOCO_GL"]
    if ctypes.util.find_library("EGL"):
        return "egl"
    if ctypes.util.find_library("OSMesa"):
        return "osmesa"
    return None


class Renderer:
    """An offscreen renderer of one model from the ``overview`` camera (close it!)."""

    def __init__(self, model: Any, size: tuple[int, int] = FRAME_SIZE, camera: str = "overview") -> None:
        import mujoco

        self._mujoco = mujoco
        try:
            with warnings.catch_warnings():  # GLFW warns before failing; the failure is reported below
                warnings.simplefilter("ignore")
                self.renderer = mujoco.Renderer(model, size[1], size[0])
        except Exception as error:  # GL context creation fails in many ways (no display, no EGL …)
            backend = os.environ.get("MUJOCO_GL", "unset")
            raise RenderUnavailable(
                f"no offscreen rendering (MUJOCO_GL={backend}): {str(error).strip().splitlines()[0]};"
                " install EGL (libegl1) or OSMesa (libosmesa6) and set MUJOCO_GL=egl or osmesa"
            ) from None
        self.camera = camera
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 1
        self._first = True

    def render(self, data: Any) -> np.ndarray:
        """An RGB image (H, W, 3) of ``data``'s current state."""
        if self._first:
            self._mujoco.mj_forward(self.renderer.model, data)
            self._first = False
        self.renderer.update_scene(data, camera=self.camera, scene_option=self.option)
        flags = self.renderer.scene.flags
        flags[self._mujoco.mjtRndFlag.mjRND_SHADOW] = False
        flags[self._mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        return np.array(self.renderer.render())

    def close(self) -> None:
        self.renderer.close()


def write_png(path: Path, image: np.ndarray) -> None:
    """Write an RGB image to ``path`` (PNG) atomically."""
    import imageio.v2 as imageio

    with atomic_path(path, suffix=".tmp.png") as tmp:
        imageio.imwrite(tmp, image)


def render_png(world: Any, path: str | Path, size: tuple[int, int] = FRAME_SIZE) -> Path:
    """Write one PNG of ``world``'s current state (a :class:`~oacdsl.runtime.simworld.SimWorld`)."""
    renderer = Renderer(world.model, size)
    try:
        write_png(Path(path), renderer.render(world.data))
    finally:
        renderer.close()
    return Path(path)


class VideoRecorder:
    """An observer that renders frames at ``fps`` into an MP4 (``out.mp4``) or, for any
    other path, into a folder of numbered PNG frames. Call :meth:`close` at the end."""

    def __init__(
        self, model: Any, out: str | Path, fps: float = 30.0, size: tuple[int, int] = FRAME_SIZE
    ) -> None:
        self.rate_hz = fps
        self.out = Path(out)
        self.renderer = Renderer(model, size)
        self.frames = 0
        self._writer: Any = None
        self._tmp = self.out
        if self.out.suffix.lower() == ".mp4":
            self._tmp = self.out.with_name(self.out.stem + ".tmp" + self.out.suffix)
            import imageio.v2 as imageio

            self.out.parent.mkdir(parents=True, exist_ok=True)
            self._writer = imageio.get_writer(
                self._tmp, fps=fps, codec="libx264", quality=7, macro_block_size=16, ffmpeg_log_level="error"
            )
        else:
            self.out.mkdir(parents=True, exist_ok=True)

    def __call__(self, world: Any) -> None:
        image = self.renderer.render(world.data)
        if self._writer is not None:
            self._writer.append_data(image)
        else:
            write_png(self.out / f"frame_{self.frames:05d}.png", image)
        self.frames += 1

    def close(self) -> Path:
        self.renderer.close()
        if self._writer is not None:
            self._writer.close()
            os.replace(self._tmp, self.out)
        return self.out


class Viewer:
    """An observer that shows the run in MuJoCo's interactive viewer (needs a display)."""

    rate_hz = 30.0

    def __init__(self, model: Any, data: Any) -> None:
        if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
            raise RenderUnavailable("no display for the interactive viewer (DISPLAY is not set)")
        try:
            import glfw

            with warnings.catch_warnings():  # GLFW warns before it fails; the failure is reported below
                warnings.simplefilter("ignore")
                ready = glfw.init()
            if not ready:  # MuJoCo's viewer would exit the process on this
                raise RenderUnavailable(
                    f"cannot open the interactive viewer on DISPLAY={os.environ.get('DISPLAY')}"
                )
            import mujoco.viewer

            self.handle = mujoco.viewer.launch_passive(model, data)
        except RenderUnavailable:
            raise
        except Exception as error:  # no GLFW, a headless MUJOCO_GL backend, …
            first = (str(error).strip().splitlines() or [type(error).__name__])[0]
            raise RenderUnavailable(f"cannot open the interactive viewer: {first}") from None

    def __call__(self, world: Any) -> None:
        self.handle.sync()

    def close(self) -> None:
        self.handle.close()
