"""Builds the Python module with CMake for `pip install --no-build-isolation .`
(docs/python.md): the project is configured for the Python that runs pip, only the module's
target is built, and the compiled module joins the package python/svetlo."""
import os
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                               "-DSVETLO_TESTS=OFF", "-DSVETLO_BENCH=OFF",
                               "-DPython_EXECUTABLE=" + sys.executable])
        subprocess.check_call(["cmake", "--build", build, "--target", "_svetlo", "-j",
                               str(os.cpu_count() or 1)])
        package = os.path.join(build, "python", "svetlo")
        built = [f for f in os.listdir(package) if f.startswith("_svetlo") and f.endswith(".so")]
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(package, built[0]), target)


setup(packages=["svetlo"], package_dir={"svetlo": "python/svetlo"},
      ext_modules=[Extension("svetlo._svetlo", sources=[])], cmdclass={"build_ext": CMakeBuild})
