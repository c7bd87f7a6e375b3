"""setuptools front end: configures the enclosing rayproof tree with CMake for this interpreter,
builds the rayproof_python target and packages the module it produces."""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        config = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                  f"-DPython_EXECUTABLE={sys.executable}", "-DRAYPROOF_PYTHON=ON",
                  "-DRAYPROOF_BUILD_TESTS=OFF", "-DRAYPROOF_BUILD_BENCH=OFF", "-DRAYPROOF_INSTALL=OFF"]
        if shutil.which("ccache"):
            config.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.run(config, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2")
        subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", "rayproof_python"], check=True)
        built = list((build / "python" / "module").glob("rayproof*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one rayproof module in {build / 'python' / 'module'}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)


setup(ext_modules=[Extension("rayproof", sources=[])], cmdclass={"build_ext": CMakeBuild})
