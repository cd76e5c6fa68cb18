"""The first start on a fresh machine: before Qt's platform plugin fails with a message nobody
can act on, ``tactile-tuner`` reads what the linker cannot find and names the library and the
apt package that holds it; the README gives the same packages in one line."""

import shutil
import subprocess
from pathlib import Path

import pytest


def test_preflight_reads_what_the_linker_cannot_find():
    from tactile_tuner.preflight import package_of, parse_ldd

    out = (
        "\tlinux-vdso.so.1 (0x00007ffd)\n"
        "\tlibxcb-cursor.so.0 => not found\n"
        "\tlibGL.so.1 => /lib/x86_64-linux-gnu/libGL.so.1 (0x00007f)\n"
        "\tlibxcb-icccm.so.4 => not found\n"
        "\tlibxcb-cursor.so.0 => not found\n"
    )
    assert parse_ldd(out) == ["libxcb-cursor.so.0", "libxcb-icccm.so.4"]
    assert package_of("libxcb-keysyms.so.1") == "libxcb-keysyms1"
    assert package_of("libxkbcommon-x11.so.0") == "libxkbcommon-x11-0"
    assert package_of("libxcb-xinput.so.0") == "libxcb-xinput0"  # by the naming rule


@pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("ldd") is None, reason="gcc")
def test_preflight_names_a_missing_library_and_its_package(tmp_path, monkeypatch):
    from tactile_tuner import preflight

    # A plugin linked against a library that is then removed: ldd reports it not found.
    (tmp_path / "dep.c").write_text("int dep(void) { return 1; }\n")
    (tmp_path / "plugin.c").write_text("int dep(void); int plugin(void) { return dep(); }\n")
    lib = tmp_path / "libxcb-gone.so.0"
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(lib), str(tmp_path / "dep.c"),
                    "-Wl,-soname,libxcb-gone.so.0"], check=True)  # fmt: skip
    plugin = tmp_path / "libqxcb.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(plugin), str(tmp_path / "plugin.c"),
                    str(lib)], check=True)  # fmt: skip
    lib.unlink()
    assert preflight.missing_libraries(plugin) == ["libxcb-gone.so.0"]
    monkeypatch.setattr(preflight, "xcb_plugin", lambda: plugin)
    line = preflight.check({"DISPLAY": ":0"})
    assert "libxcb-gone.so.0" in line and "apt-get install libxcb-gone0" in line
    assert preflight.check({"QT_QPA_PLATFORM": "offscreen"}) == ""
    assert preflight.check({}).startswith("no display")


def test_the_readme_names_the_window_libraries_in_one_line():
    from tactile_tuner.preflight import APT_LINE

    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    assert APT_LINE in readme
    for package in ("python3-venv", "libxcb-cursor0", "libxcb-icccm4", "libxcb-keysyms1"):
        assert package in APT_LINE
