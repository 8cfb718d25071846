"""Builds loopsub._loopsub with the project's CMake for the interpreter that runs this (see pyproject.toml)."""
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, extension):
        tag = sysconfig.get_config_var("EXT_SUFFIX").split(".")[1]  # cpython-311-x86_64-linux-gnu
        build = ROOT / "build-python" / tag
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython_EXECUTABLE={sys.executable}", f"-DPYTHON_EXECUTABLE={sys.executable}",
                     "-DLOOPSUB_TESTS=OFF", "-DLOOPSUB_BENCH=OFF", "-DLOOPSUB_BLENDER=", "-DLOOPSUB_COPY_TO_ADDON=OFF"]
        try:  # pybind11 from PyPI where the build has it (wheels, other platforms); else CMake finds Debian's
            import pybind11
            configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
        except ImportError:
            pass
        subprocess.run(configure, check=True)
        # --config: multi-configuration generators (Visual Studio) build Debug by default.
        subprocess.run(["cmake", "--build", str(build), "--config", "Release", "--target", "_loopsub",
                        "-j", str(os.cpu_count() or 1)], check=True)
        # Visual Studio puts it in native/Release/.
        built = next((build / "native").rglob("_loopsub*" + sysconfig.get_config_var("EXT_SUFFIX")))
        target = pathlib.Path(self.get_ext_fullpath(extension.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[Extension("loopsub._loopsub", sources=[])], cmdclass={"build_ext": CMakeBuild})
