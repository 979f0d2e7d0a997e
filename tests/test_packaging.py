"""pyproject.toml: a light core with the heavy parts as extras, an SPDX licence, typed packages."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
HEAVY = {"mujoco", "mink", "pin", "frankik", "example-robot-data", "daqp", "imageio", "clingo", "dask", "distributed"}


def _name(requirement: str) -> str:
    return requirement.split(";")[0].split("[")[0].split(">")[0].split("=")[0].split("<")[0].strip().lower()


def test_the_core_has_no_heavy_dependency_and_the_extras_have_them():
    core = {_name(r) for r in PROJECT["dependencies"]}
    assert not core & HEAVY, core & HEAVY
    extras = PROJECT["optional-dependencies"]
    assert {"arms", "sim", "asp", "dask", "all", "test", "docs"} <= set(extras)
    assert {_name(r) for r in extras["arms"]} == {"mujoco", "mink", "pin", "frankik", "example-robot-data", "daqp",
                                                 "imageio"}
    assert {_name(r) for r in extras["asp"]} == {"clingo"}
    assert extras["all"] == ["delkit[arms,sim,asp,dask,view]"]


def test_every_plugin_names_an_extra_that_exists():
    import arms.cli
    import sim.cli

    for plugin in (arms.cli, sim.cli):
        assert plugin.EXTRA in PROJECT["optional-dependencies"]


def test_spdx_licence_with_its_file_and_typed_packages():
    assert PROJECT["license"] == "MIT"  # an SPDX expression, not the deprecated {text = ...} table
    assert PROJECT["license-files"] == ["LICENSE"]
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["*"]
    assert "py.typed" in data
    for package in ("delkit", "planners", "sim", "arms"):
        assert (ROOT / package / "py.typed").exists()
