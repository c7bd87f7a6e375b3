"""setuptools front end: builds the rayproof_python target with CMake and packages the module it
produces, for the interpreter that runs pip.

Where it builds:
- RAYPROOF_CMAKE_BUILD_DIR=DIR: in that already configured build tree of this source (one with the
  Python module on, for this Python version), so that only what is out of date is built; after
  `cmake --build DIR --target rayproof_python` this is nothing.
- otherwise: a private build under python/build/ (tests and benchmarks off), configured here.
CMAKE_BUILD_PARALLEL_LEVEL sets the build jobs (default 2); CMAKE, the cmake program (default: cmake)."""
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


def cache_value(build, key):
    """The value of `key` in build/CMakeCache.txt, or None."""
    for line in (build / "CMakeCache.txt").read_text(errors="replace").splitlines():
        name, _, value = line.partition("=")
        if name.split(":", 1)[0] == key:
            return value
    return None


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        cmake = os.environ.get("CMAKE", "cmake")
        existing = os.environ.get("RAYPROOF_CMAKE_BUILD_DIR")
        if existing:
            build = pathlib.Path(existing).resolve()
            if not (build / "CMakeCache.txt").is_file():
                raise RuntimeError(f"RAYPROOF_CMAKE_BUILD_DIR={existing}: not a configured CMake build tree "
                                   "(no CMakeCache.txt)")
            if (cache_value(build, "RAYPROOF_PYTHON") or "").upper() not in ("ON", "TRUE", "1", "YES"):
                raise RuntimeError(f"RAYPROOF_CMAKE_BUILD_DIR={existing}: the Python module is off there "
                                   "(configure it with -DRAYPROOF_PYTHON=ON)")
        else:
            build = pathlib.Path(self.build_temp).resolve() / "cmake"
            config = [cmake, "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                      f"-DPython_EXECUTABLE={sys.executable}", "-DRAYPROOF_PYTHON=ON",
                      "-DRAYPROOF_BUILD_TESTS=OFF", "-DRAYPROOF_BUILD_BENCH=OFF", "-DRAYPROOF_INSTALL=OFF"]
            if shutil.which("ccache"):
                config += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
            subprocess.run(config, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2")
        subprocess.run([cmake, "--build", str(build), "-j", jobs, "--target", "rayproof_python"], check=True)
        built = list((build / "python" / "module").glob("rayproof*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one rayproof module in {build / 'python' / 'module'}, found {built}")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        if not built[0].name.endswith(suffix):
            raise RuntimeError(f"{built[0]} is not for this Python ({sys.executable} loads modules named "
                               f"rayproof{suffix}); configure that build with -DPython_EXECUTABLE={sys.executable}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)


setup(ext_modules=[Extension("rayproof", sources=[])], cmdclass={"build_ext": CMakeBuild})
