"""Offscreen rendering of recorded runs to PNG frames and a GIF/MP4 (EGL, else OSMesa).

MuJoCo picks its OpenGL platform from ``MUJOCO_GL`` when ``mujoco`` is first imported, so rendering runs
in a child process (``python -m arms.render``) with ``MUJOCO_GL`` set: the parent (which has already
imported mujoco for the physics) is unaffected, and a GL driver that crashes cannot take the run with it.
:func:`gl_backend` probes ``egl`` then ``osmesa`` once per process; where neither works (no libEGL, no
``libosmesa6``) rendering is skipped with the reason.

Frames are qpos snapshots: the child compiles the same MJCF, sets qpos, runs ``mj_kinematics`` (and
``mj_camlight``) and
renders from a named camera.
"""

from __future__ import annotations

import functools
import os
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np

__all__ = ["gl_backend", "render_frames", "RenderSkipped"]

_PROBE = ("import mujoco; m = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom size=\"1\"/>"
          "</worldbody></mujoco>'); r = mujoco.Renderer(m, 32, 32); d = mujoco.MjData(m); "
          "mujoco.mj_forward(m, d); r.update_scene(d); assert r.render().shape == (32, 32, 3)")


class RenderSkipped(RuntimeError):
    """No OpenGL platform is available; the message says why and how to get one."""


@functools.lru_cache(maxsize=1)
def gl_backend() -> tuple[str | None, str]:
    """(backend, reason): the first of ``MUJOCO_GL`` (if set), egl, osmesa that can render offscreen."""
    tried = []
    wanted = os.environ.get("MUJOCO_GL")
    for backend in ([wanted] if wanted in ("egl", "osmesa") else []) + ["egl", "osmesa"]:
        env = dict(os.environ, MUJOCO_GL=backend, PYOPENGL_PLATFORM=backend)
        try:
            proc = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True,
                                  timeout=60)
        except subprocess.TimeoutExpired:
            tried.append(f"{backend}: timed out")
            continue
        if proc.returncode == 0:
            return backend, f"rendering with MUJOCO_GL={backend}"
        last = (proc.stderr.strip().splitlines() or ["failed"])[-1]
        tried.append(f"{backend}: {last[:120]}")
    return None, ("no OpenGL for offscreen rendering (" + "; ".join(tried) + "); install EGL (libegl1) "
                  "or OSMesa (Debian: apt-get install libosmesa6) to get pictures")


def render_frames(xml: str, frames: Sequence[np.ndarray], out_dir: str | Path, *, camera: str = "overview",
                  width: int = 640, height: int = 480, fps: float = 25.0, video: bool = True,
                  still: str = "final.png", save_frames: bool = False, timeout: float = 600.0,
                  ) -> dict[str, str]:
    """Render qpos ``frames`` of the model ``xml`` to ``out_dir``: the last frame as PNG, all as GIF/MP4,
    and with ``save_frames`` every frame as ``frames/frame_NNNN.png``.

    Returns ``{"png": path, "video": path, "frames": dir}``; raises :class:`RenderSkipped` if no GL is
    available.
    """
    backend, reason = gl_backend()
    if backend is None:
        raise RenderSkipped(reason)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        xml_path = Path(tmp) / "scene.xml"
        xml_path.write_text(xml)
        npz = Path(tmp) / "frames.npz"
        np.savez(npz, qpos=np.asarray(frames, dtype=float))
        args = [sys.executable, "-m", "arms.render", str(xml_path), str(npz), str(out), camera, str(width),
                str(height), str(fps), "1" if video else "0", still, "1" if save_frames else "0"]
        env = dict(os.environ, MUJOCO_GL=backend, PYOPENGL_PLATFORM=backend)
        proc = subprocess.run(args, env=env, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise RenderSkipped(f"rendering failed: {(proc.stderr.strip().splitlines() or ['?'])[-1]}")
    files = {}
    for line in proc.stdout.splitlines():
        key, _, val = line.partition("=")
        if key in ("png", "video", "frames"):
            files[key] = val
    return files


def _child(argv: list[str]) -> int:
    """Child process: render frames (MUJOCO_GL already set by the parent)."""
    xml_path, npz, out, camera, width, height, fps, video, still, save_frames = argv
    import imageio.v2 as imageio
    import mujoco

    model = mujoco.MjModel.from_xml_path(xml_path)
    data = mujoco.MjData(model)
    qpos = np.load(npz)["qpos"]
    renderer = mujoco.Renderer(model, int(height), int(width))

    def frame(q: np.ndarray, shadows: bool) -> np.ndarray:
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_camlight(model, data)  # cameras and lights follow the bodies
        renderer.update_scene(data, camera=camera)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
        return renderer.render().copy()

    # animation frames without shadows (3x faster with a software GL), the still with them
    images = [frame(q, False) for q in qpos[:-1]] + [frame(qpos[-1], True)]
    out_dir = Path(out)
    png = out_dir / still
    imageio.imwrite(png, images[-1])
    print(f"png={png}")
    if save_frames == "1":
        fdir = out_dir / "frames"
        fdir.mkdir(exist_ok=True)
        for i, img in enumerate(images):
            imageio.imwrite(fdir / f"frame_{i:04d}.png", img)
        print(f"frames={fdir}")
    if video == "1" and len(images) > 1:
        try:
            path = out_dir / "run.mp4"
            imageio.mimsave(path, images, fps=float(fps))
        except Exception:  # no ffmpeg plugin: fall back to an animated GIF
            path = out_dir / "run.gif"
            imageio.mimsave(path, images[::2], duration=2.0 / float(fps), loop=0)
        print(f"video={path}")
    return 0


if __name__ == "__main__":
    sys.exit(_child(sys.argv[1:]))
