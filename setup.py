"""pip install --no-build-isolation .  — the Python package spectral_skin.

The compiled module is built by the project's CMake build (the one build of the libraries; no
second list of sources here), using only Debian's tools: cmake, a C++ compiler, pybind11-dev /
python3-pybind11, python3-dev, python3-numpy, python3-setuptools. Environment:
  SKIN_BUILD_DIR  an already configured build tree to build the module in (e.g. build/, as
                  scripts/test.sh does); default: a fresh one under setuptools' build_temp.
  SKIN_CMAKE_ARGS extra arguments for the configure step of a fresh build tree.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(spectral_skin VERSION ([0-9.]+)", f.read()).group(1)


class CMakeBuild(build_ext):
    """Builds the target spectral_skin (python/CMakeLists.txt) and copies the package files."""

    def build_extension(self, ext):
        build_dir = os.environ.get("SKIN_BUILD_DIR")
        if build_dir:
            build_dir = os.path.abspath(build_dir)
        else:
            build_dir = os.path.abspath(os.path.join(self.build_temp, "cmake"))
            configure = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                         "-DSKIN_BUILD_TESTS=OFF", "-DSKIN_BUILD_BENCH=OFF",
                         "-DSKIN_BUILD_PYTHON=ON", f"-DPYTHON_EXECUTABLE={sys.executable}"]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            configure += shlex.split(os.environ.get("SKIN_CMAKE_ARGS", ""))
            subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", build_dir, "--target", "spectral_skin"], check=True)
        built = os.path.join(build_dir, "python", "spectral_skin")
        target = os.path.dirname(self.get_ext_fullpath(ext.name))
        os.makedirs(target, exist_ok=True)
        for name in os.listdir(built):
            if name.startswith("_core") or name.endswith(".pyi"):
                shutil.copy2(os.path.join(built, name), target)


os.makedirs(os.path.join(ROOT, ".setuptools-build"), exist_ok=True)
setup(
    name="spectral_skin",
    version=version(),
    description="Physically based skin appearance from four biophysical numbers "
                "(Donner & Jensen 2006, and beyond)",
    packages=["spectral_skin"],
    package_dir={"": "python"},
    package_data={"spectral_skin": ["py.typed", "__init__.pyi"]},
    ext_modules=[Extension("spectral_skin._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    python_requires=">=3.9",
    zip_safe=False,
    # setuptools' own build files away from CMake's build/ of the project.
    options={"build": {"build_base": ".setuptools-build"}, "egg_info": {"egg_base": ".setuptools-build"}},
)
