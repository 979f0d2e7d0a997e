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


def test_every_spec_file_is_package_data_of_the_wheel():
    """specs/ ships as planners/specs (a link in the checkout): every file there matches a package-data
    pattern, so `delkit demo` and `delkit epico` find them in a wheel (bench/packaging.py installs one)."""
    from fnmatch import fnmatch

    link = ROOT / "planners" / "specs"
    assert link.is_symlink() and link.resolve() == (ROOT / "specs").resolve()
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    patterns = data["package-data"]["*"]
    assert "planners.specs*" not in data["packages"]["find"].get("exclude", [])
    files = [p for p in (ROOT / "specs").rglob("*") if p.is_file()]
    assert files
    missing = [str(p.relative_to(ROOT)) for p in files if not any(fnmatch(p.name, pat) for pat in patterns)]
    assert not missing, f"not packaged (add a pattern to package-data): {missing}"
    from planners.demo import specs_dir
    from planners.epico import domain_path

    assert specs_dir() == Path(__import__("planners").__file__).resolve().parent / "specs"
    assert domain_path().is_file()


def test_demo_skips_a_section_whose_extra_is_missing(tmp_path, monkeypatch):
    """A light install: `delkit demo` runs what is installed and reports the rest as skipped, naming the extra."""
    from delkit.cli import core_cmd, plugins
    from delkit.errors import require_extra

    def needs_extra(out):
        require_extra("arms", "no_such_module_for_this_test", what="the arms demo")

    monkeypatch.setattr(plugins, "demo_sections", lambda: [(1, "core", lambda out: {"ok": True}),
                                                            (2, "arms", needs_extra)])
    records = core_cmd.run_demo(tmp_path)
    assert [r["ok"] for r in records] == [True, None]
    assert "delkit[arms]" in records[1]["result"]["summary"]
