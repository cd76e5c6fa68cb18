"""The wheel must carry every package of the source tree (pyproject lists them explicitly,
because assets/ is mapped into tactile_core._assets)."""

from pathlib import Path

import tomllib

ROOT = Path(__file__).resolve().parents[1]


def test_every_source_package_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    found = {
        ".".join(init.parent.relative_to(ROOT).parts)
        for init in (ROOT / "tactile_core").rglob("__init__.py")
        if "__pycache__" not in init.parts
    }
    assert found <= listed, f"missing from pyproject packages: {sorted(found - listed)}"
    # The GUI lives in app/ but installs under its own name, not a generic top-level "app".
    assert "app" not in listed and config["package-dir"]["tactile_tuner"] == "app"
    # app/'s sub-packages install under tactile_tuner (the mapping covers them), so each must
    # be listed as tactile_tuner.<name>.
    gui = {
        ".".join(("tactile_tuner", *init.parent.relative_to(ROOT / "app").parts))
        for init in (ROOT / "app").rglob("*/__init__.py")
        if "__pycache__" not in init.parts
    }
    assert gui, "app/ has sub-packages (controls, experiments, tune, views)"
    assert gui <= listed, f"missing from pyproject packages: {sorted(gui - listed)}"
    mapped = {name for name in listed if name.startswith("tactile_core._assets")}
    assert config["package-dir"]["tactile_core._assets"] == "assets"
    for name in mapped - {"tactile_core._assets"}:
        folder = ROOT / "assets" / name.split(".")[-1]
        assert folder.is_dir() and any(folder.glob("*.json")), name


def test_the_gui_installs_as_tactile_tuner_and_the_core_reaches_its_bench_by_entry_point():
    from importlib.metadata import entry_points

    hooks = {ep.name: ep.value for ep in entry_points(group="tactile.bench")}
    assert hooks.get("gui") == "tactile_tuner.bench:run"
    import tactile_tuner.main

    assert tactile_tuner.main.__file__.endswith("app/main.py")
