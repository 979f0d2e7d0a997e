"""What the arms layer needs beyond the core: the pip extra ``delkit[arms]`` and the modules it provides
(read by :func:`delkit.errors.require_extra` before any of them is imported)."""

EXTRA = "arms"
REQUIRES = ("mujoco", "mink", "pinocchio", "frankik")
