"""The import paths of 0.1 keep working for one release, and say where things went."""

import subprocess
import sys

import pytest

import tactile_core as tc
from tactile_core import _compat


@pytest.mark.parametrize("old", sorted(_compat.MOVED))
def test_every_old_path_gives_the_new_object_and_warns(old):
    new = _compat.MOVED[old]
    module = sys.modules[old]
    real = __import__(new, fromlist=["_"])
    public = [n for n in vars(real) if not n.startswith("__")]
    name = public[0]
    with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
        assert getattr(module, name) is getattr(real, name)


def test_from_import_of_an_old_path_warns_and_names_the_new_one():
    code = (
        "import warnings; warnings.simplefilter('error')\n"
        "try:\n"
        "    from tactile_core.scene import Scene\n"
        "except DeprecationWarning as exc:\n"
        "    print(exc)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "tactile_core.rendering.scene" in out.stdout and "0.3" in out.stdout


def test_the_public_face_never_warns_and_render_stays_a_function():
    code = (
        "import warnings; warnings.simplefilter('error')\n"
        "import numpy as np\n"
        "import tactile_core as tc\n"
        "f = tc.render(tc.Line((0.5, 1.84), (4.5, 4.16)), 'AS', np.linspace(0, 1, 3))\n"
        "import warnings; warnings.simplefilter('ignore')\n"
        "from tactile_core.render import render_xy\n"  # the old module path of 0.1
        "assert callable(tc.render) and tc.render.__name__ == 'render', tc.render\n"
        "print(f.shape)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "(3, 6, 5)"


def test_the_old_device_module_names_come_from_the_profile_module():
    from tactile_core.device import profile

    with pytest.warns(DeprecationWarning, match="tactile_core.device.profile"):
        assert tc.device.DEFAULT_PROFILE == profile.DEFAULT_PROFILE
    with pytest.raises(AttributeError):
        tc.device.no_such_name  # noqa: B018


def test_an_unknown_attribute_is_still_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_module"):
        tc.no_such_module  # noqa: B018
