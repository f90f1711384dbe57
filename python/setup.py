"""Builds libfemto and the scene reader from this checkout with CMake, then femto's cffi
extension against them; the shared library travels inside the package (found by $ORIGIN).

FEMTO_CMAKE_BUILD=DIR reuses a CMake build of this checkout that already has libfemto.so and
libfemto_scene.a (configured with -DFEMTO_BUILD_CLI=ON); otherwise one is made in
python/_cmake_build (Release, the library and the scene reader only).
"""
import glob
import os
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_ext import build_ext

# What the build needs, said before pip's own error (which names none of it).
for module, package in (("cffi", "python3-cffi"), ("wheel", "python3-wheel")):
    try:
        __import__(module)
    except ImportError:
        sys.exit("femto: building the package needs %s (Debian: %s), which %s does not see. "
                 "Make the venv from Debian's Python, which has it: /usr/bin/python3 -m venv "
                 "--system-site-packages .venv (another python3 first on PATH, such as pyenv's, "
                 "has neither Debian's packages nor a registry to fetch them from)."
                 % (module, package, sys.executable))

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
import femto_build  # noqa: E402


def cmake_build():
    given = os.environ.get("FEMTO_CMAKE_BUILD")
    if given:
        build = os.path.abspath(given)
    else:
        build = os.path.join(HERE, "_cmake_build")
        subprocess.run(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                        "-DFEMTO_BUILD_CLI=ON", "-DFEMTO_BUILD_TESTS=OFF",
                        "-DFEMTO_BUILD_VIEWER=OFF", "-DFEMTO_BUILD_EXAMPLES=OFF",
                        "-DFEMTO_INSTALL=OFF", "-DFEMTO_SANITIZE=OFF"], check=True)
    jobs = str(os.cpu_count() or 2)
    subprocess.run(["cmake", "--build", build, "-j", jobs, "--target", "femto_shared",
                    "femto_scene"], check=True)
    libraries = sorted(glob.glob(os.path.join(build, "libfemto.so.*.*.*")))
    scene = os.path.join(build, "cli", "libfemto_scene.a")
    if not libraries or not os.path.exists(scene):
        sys.exit("setup.py: %s has no libfemto.so.X.Y.Z or cli/libfemto_scene.a" % build)
    return build, libraries[-1], scene


class BuildWithFemto(build_ext):
    """Builds the C library first, puts it beside the extension, links the extension to it."""

    def run(self):
        build, library, scene = cmake_build()
        soname = os.path.basename(library).rsplit(".", 1)[0]  # libfemto.so.MAJOR.MINOR
        for target in (os.path.join(self.build_lib, "femto"), os.path.join(HERE, "femto")):
            os.makedirs(target, exist_ok=True)
            shutil.copy2(library, os.path.join(target, soname))
        for ext in self.extensions:
            ext.library_dirs.append(build)
            ext.extra_objects.append(scene)
        super().run()


ffibuilder = femto_build.make_builder(library_dirs=[], libraries=["femto", "cjson", "m"],
                                      extra_objects=[], runtime_dirs=["$ORIGIN"])

setup(ext_modules=[ffibuilder.distutils_extension()], cmdclass={"build_ext": BuildWithFemto},
      zip_safe=False)
