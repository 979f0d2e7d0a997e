"""Offscreen rendering (skipped where no OpenGL is available)."""

from __future__ import annotations

import numpy as np
import pytest

from arms.demo import demo_plan
from arms.render import gl_backend, render_frames
from arms.scene import build_scene

pytestmark = pytest.mark.gl


def test_render_initial_scene_to_png(tmp_path):
    backend, reason = gl_backend()
    if backend is None:
        pytest.skip(reason)
    import imageio.v2 as imageio

    scene = build_scene(demo_plan().world)
    q0 = scene.model.key("home").qpos.copy()
    files = render_frames(scene.spec.to_xml(), [q0, q0], tmp_path, width=320, height=240, video=True)
    img = imageio.imread(files["png"])
    assert img.shape == (240, 320, 3)
    assert img.std() > 10  # not a blank frame
    # the red block is in the picture
    r, g, b = (img[..., k].astype(int) for k in range(3))
    red = (r > 60) & (r > 3 * g) & (r > 3 * b)
    assert red.sum() > 5
    assert files["video"].endswith((".gif", ".mp4"))


def test_rendering_is_skipped_with_a_reason_without_gl(monkeypatch, tmp_path):
    import arms.render as render

    monkeypatch.setattr(render, "gl_backend", lambda: (None, "no OpenGL here (test)"))
    with pytest.raises(render.RenderSkipped, match="no OpenGL"):
        render.render_frames("<mujoco/>", [np.zeros(1)], tmp_path)
