"""cmake --install puts a module that imports: staged with DESTDIR at RAYPROOF_PYTHON_INSTALL_DIR."""
import os
import pathlib
import subprocess
import sys

import pytest

CMAKE = os.environ.get("RAYPROOF_CMAKE")
BUILD = os.environ.get("RAYPROOF_BUILD_DIR")


@pytest.mark.skipif(not (CMAKE and BUILD), reason="run from ctest (RAYPROOF_CMAKE, RAYPROOF_BUILD_DIR)")
def test_install_component_python(tmp_path):
    env = dict(os.environ, DESTDIR=str(tmp_path))
    subprocess.run([CMAKE, "--install", BUILD, "--component", "python", "--prefix", "/prefix"], env=env,
                   check=True, capture_output=True)
    found = list(tmp_path.rglob("rayproof*.so"))
    assert len(found) == 1
    env = dict(os.environ, PYTHONPATH=str(found[0].parent))
    out = subprocess.run([sys.executable, "-c", "import rayproof; print(rayproof.__file__, len(rayproof.methods()))"],
                         env=env, check=True, capture_output=True, text=True, cwd=tmp_path).stdout
    assert out.startswith(str(found[0]))
