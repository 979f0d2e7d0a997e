"""The built-in two-robot plan (seed 004, Sec. 4.4 / Listing 5) and :func:`run_demo` for ``delkit demo``.

robot1 senses its stack 1, finds *red* under *black*, moves *black* onto *green* (stack 0), puts *red* on
the shared table and announces it; robot2 takes *red* from the shared table to its own stack 1.
"""

from __future__ import annotations

import json
from pathlib import Path

from arms.plan import Plan, parse_plan

__all__ = ["demo_plan", "run_demo", "execute_and_render"]


def demo_plan() -> Plan:
    """The built-in plan (``arms/demo_plan.json``)."""
    text = (Path(__file__).resolve().parent / "demo_plan.json").read_text()
    return parse_plan(json.loads(text), source="arms/demo_plan.json")


def execute_and_render(plan: Plan, out_dir: Path | None, *, grasp: str = "friction", render: bool = True,
                       video: bool = False, fps: float = 10.0, save_scene: bool = True, progress=None,
                       tolerance: float = 0.01, save_frames: bool = False):
    """Run ``plan`` in physics; if ``out_dir`` is given write scene.xml, result.json and pictures.

    Returns (RunResult with ``files`` filled in, message about rendering).
    """
    from dataclasses import replace

    from arms.executor import run_plan
    from arms.render import RenderSkipped, render_frames
    from arms.scene import save_mjcf
    from arms.world import ArmsError

    if out_dir is not None:  # before the (long) simulation: an unusable directory is bad input
        try:
            Path(out_dir).mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise ArmsError(f"{out_dir}: cannot create the output directory: {exc.strerror}; "
                            f"give a writable --out directory") from None
    record = fps if (render and (video or save_frames) and out_dir is not None) else 0.0
    result, ex = run_plan(plan, grasp=grasp, record_fps=record, progress=progress,
                           tolerance=tolerance)
    files: dict[str, str] = {}
    note = "rendering not requested"
    if out_dir is not None:
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        if save_scene:
            files["scene"] = str(save_mjcf(ex.scene, out_dir / "scene.xml"))
        if render:
            frames = ex.frames if ex.frames else []
            frames = [*frames, ex.data.qpos.copy()]
            try:
                size = (480, 360) if len(frames) > 1 else (640, 480)
                files.update(render_frames(ex.scene.spec.to_xml(), frames, out_dir, video=video, fps=fps,
                                           width=size[0], height=size[1], save_frames=save_frames))
                note = f"wrote {files.get('png')}" + (f" and {files['video']}" if "video" in files else "")
            except RenderSkipped as exc:
                note = f"picture skipped: {exc}"
    result = replace(result, files=files)
    if out_dir is not None:
        (Path(out_dir) / "result.json").write_text(json.dumps(result.to_json(), indent=2))
        files["result"] = str(Path(out_dir) / "result.json")
    return result, note


def run_demo(out_dir: Path, render: bool = True, video: bool = False) -> dict:
    """Run the built-in two-robot plan; write ``out_dir/final.png`` if GL is available.

    Returns ``{"success", "png" (path or None), "note" (what was written or why the picture was skipped),
    "sim_seconds", "wall_seconds", "realtime_factor", "max_block_error_m", "failure"}``.
    """
    result, note = execute_and_render(demo_plan(), Path(out_dir), render=render, video=video)
    errs = [a.max_block_error for a in result.actions if a.max_block_error == a.max_block_error]
    return {"success": result.success, "png": result.files.get("png"), "note": note,
            "sim_seconds": result.sim_seconds, "wall_seconds": result.wall_seconds,
            "realtime_factor": result.realtime_factor, "max_block_error_m": max(errs, default=0.0),
            "failure": result.failure}
