"""`pip install .`: builds the aniso Python module with CMake (python/CMakeLists.txt) and installs
the package (python/aniso). Offline, with Debian's packages: see docs/python.md, "Install".

    /usr/bin/python3 -m venv --system-site-packages .venv
    .venv/bin/pip install --no-build-isolation --no-index .
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
# The one version: project(aniso VERSION x.y.z) in CMakeLists.txt.
VERSION = re.search(r"project\(aniso VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)


class CMakeBuild(build_ext):
    """Configures a build tree of its own (build/pip, for the installing interpreter), builds the
    module target and copies the module where setuptools packs it."""

    def build_extension(self, ext):
        build_dir = ROOT / "build" / "pip"
        subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                               f"-DPython_EXECUTABLE={sys.executable}", "-DANISO_BUILD_TESTS=OFF",
                               "-DANISO_BUILD_BENCH=OFF"])
        subprocess.check_call(["cmake", "--build", str(build_dir), "--target", "aniso_python", "-j",
                               os.environ.get("JOBS", str(os.cpu_count() or 2))])
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(build_dir / "python" / "aniso" / target.name, target)


setup(
    name="aniso",
    version=VERSION,
    description="Anisotropic and measured reflectance: BRDF models, sampling, metals, a path tracer",
    packages=["aniso"],
    package_dir={"": "python"},
    package_data={"aniso": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("aniso._aniso", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    # aniso.fit_many on a Dask cluster (docs/fit-db.md); its report's figure.
    extras_require={"dask": ["distributed"], "report": ["matplotlib"]},
    python_requires=">=3.9",
    zip_safe=False,
)
