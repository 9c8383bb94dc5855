"""pip install ./ : the Python package ``ricci`` with its extension built by the project's CMake.

    python3 -m venv --system-site-packages venv    # numpy from Debian's python3-numpy
    venv/bin/pip install ./                        # or: pip wheel ./ -w dist
    venv/bin/python -c "import ricci; print(ricci.__version__)"

Offline on purpose: there is no pyproject.toml, so pip (23.0, Debian 12) builds with the
setuptools and wheel it already has instead of downloading them into an isolated build
environment. build_ext configures CMake (Release; no tests, benchmarks or fuzzers), builds the
targets ``_ricci`` (the extension) and ``ricci`` (the command line, which ``ricci.batch`` runs),
and puts into the package: python/ricci/*.py, ``_ricci*.so``, ``bin/ricci`` and, when MPI was
found, ``bin/ricci-mpi.so`` (the module `ricci batch` loads under mpirun).

Environment:
  RICCI_CMAKE_BUILD_DIR   a CMake build folder to use and keep (default: a temporary one,
                          removed afterwards). Configured here when it has no CMakeCache.txt;
                          otherwise built as it is configured (e.g. a developer's build tree),
                          which makes a second pip build nearly free.
  CMAKE_BUILD_PARALLEL_LEVEL  compiler jobs (default: the number of CPUs).
  RICCI_CMAKE_ARGS        extra arguments for the configure step, split on white space.
"""

import atexit
import glob
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def project_version():
    """The version of CMake's project() in CMakeLists.txt: the one source of the version."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(\s*ricci\s+VERSION\s+([0-9][0-9.]*)", f.read())
    if not match:
        raise RuntimeError("setup.py: no project(ricci VERSION ...) in CMakeLists.txt")
    return match.group(1)


def cache_value(cache, name):
    """A variable's value in a CMakeCache.txt, or None."""
    with open(cache, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith(name + ":"):
                return line.split("=", 1)[1].strip()
    return None


# setuptools' own scratch folders ("build/", "*.egg-info") would land in the checkout, and
# build/ is where the README puts the CMake build: keep them out of the source tree.
_scratch = tempfile.mkdtemp(prefix="ricci-setuptools-")
atexit.register(shutil.rmtree, _scratch, True)


def pip_failure_marker():
    """When pip runs this script: a file that says the build failed under this pip process. pip
    23.0 answers a failed `setup.py bdist_wheel` with `setup.py install`, which would compile
    everything a second time only to fail again; the marker makes that second try stop at once.
    None when the parent is not pip (a person running setup.py builds every time)."""
    try:
        with open(f"/proc/{os.getppid()}/cmdline", "rb") as f:
            parent = f.read().replace(b"\0", b" ")
    except OSError:
        return None
    if b"pip" not in parent:
        return None
    return os.path.join(tempfile.gettempdir(), f"ricci-setup-failed-{os.getppid()}")


class CMakeBuild(build_ext):
    """Builds the extension and the ricci program with CMake and copies them into the package."""

    def run(self):
        marker = pip_failure_marker()
        if marker and os.path.exists(marker):
            os.remove(marker)
            raise RuntimeError("setup.py: the CMake build failed a moment ago under this pip "
                               "(its output is above); not building it a second time")
        try:
            build_dir = os.environ.get("RICCI_CMAKE_BUILD_DIR")
            if build_dir:
                self.cmake_build(os.path.abspath(build_dir))
                return
            build_dir = tempfile.mkdtemp(prefix="ricci-cmake-")
            try:
                self.cmake_build(build_dir)
            finally:
                shutil.rmtree(build_dir, ignore_errors=True)
        except BaseException:
            if marker:
                open(marker, "wb").close()
            raise

    def cmake_build(self, build_dir):
        cmake = os.environ.get("CMAKE", "cmake")
        python = os.path.realpath(sys.executable)  # a venv's python is a link to the interpreter
        cache = os.path.join(build_dir, "CMakeCache.txt")
        if os.path.exists(cache):
            configured = cache_value(cache, "PYTHON_EXECUTABLE")
            if configured and os.path.realpath(configured) != python:
                raise RuntimeError(
                    f"setup.py: RICCI_CMAKE_BUILD_DIR={build_dir} builds the module for "
                    f"{configured}, not for {sys.executable}; use another folder")
            if (cache_value(cache, "BUILD_SHARED_LIBS") or "OFF").upper() in ("ON", "1", "TRUE"):
                raise RuntimeError(f"setup.py: {build_dir} builds a shared libricci, which the "
                                   "package does not carry; use a folder with static libraries")
        else:
            os.makedirs(build_dir, exist_ok=True)
            configure = [
                cmake, "-S", ROOT, "-B", build_dir,
                "-DCMAKE_BUILD_TYPE=Release",
                f"-DPYTHON_EXECUTABLE={python}",
                "-DRICCI_BUILD_PYTHON=ON",
                "-DRICCI_BUILD_TESTS=OFF",
                "-DRICCI_BUILD_BENCH=OFF",
                "-DRICCI_FUZZ=OFF",
                "-DRICCI_SANITIZE=OFF",
                "-DBUILD_SHARED_LIBS=OFF",
            ] + os.environ.get("RICCI_CMAKE_ARGS", "").split()
            self.announce("configuring: " + " ".join(configure), level=2)
            subprocess.check_call(configure)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.check_call([cmake, "--build", build_dir, "--config", "Release",
                               "--target", "_ricci", "ricci", "--parallel", jobs])
        # (ricci depends on its MPI module, ricci_mpi, when MPI is found: built with it.)

        # The extension: CMake puts it inside <build>/python/ricci for every configuration.
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        extension = os.path.join(build_dir, "python", "ricci", "_ricci" + suffix)
        if not os.path.isfile(extension):
            found = glob.glob(os.path.join(build_dir, "python", "ricci", "_ricci*"))
            raise RuntimeError(f"setup.py: CMake built no {extension} (found: {found})")
        # The program: <build>/ricci, or <build>/Release/ricci with a multi-config generator.
        program = next((p for p in (os.path.join(build_dir, "ricci"),
                                    os.path.join(build_dir, "Release", "ricci"))
                        if os.path.isfile(p) and os.access(p, os.X_OK)), None)
        if program is None:
            raise RuntimeError(f"setup.py: CMake built no ricci program in {build_dir}")

        target = self.get_ext_fullpath("ricci._ricci")
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(extension, target)
        shutil.copymode(extension, target)
        # ricci.batch runs this one first (python/ricci/_batch.py, find_program).
        bin_dir = os.path.join(os.path.dirname(target), "bin")
        os.makedirs(bin_dir, exist_ok=True)
        shutil.copyfile(program, os.path.join(bin_dir, "ricci"))
        os.chmod(os.path.join(bin_dir, "ricci"), 0o755)
        # `ricci batch` under mpirun loads its MPI module from beside the program (built when
        # CMake found MPI).
        mpi_module = os.path.join(os.path.dirname(program), "ricci-mpi.so")
        if os.path.isfile(mpi_module):
            shutil.copyfile(mpi_module, os.path.join(bin_dir, "ricci-mpi.so"))

    def get_outputs(self):
        bin_dir = os.path.join(os.path.dirname(self.get_ext_fullpath("ricci._ricci")), "bin")
        outputs = [os.path.join(bin_dir, "ricci")]
        if os.path.isfile(os.path.join(bin_dir, "ricci-mpi.so")):
            outputs.append(os.path.join(bin_dir, "ricci-mpi.so"))
        return super().get_outputs() + outputs


setup(
    name="ricci",
    version=project_version(),
    description="Discrete surface Ricci flow and conformal parameterization of triangle meshes",
    long_description=open(os.path.join(ROOT, "python", "README.md"), encoding="utf-8").read(),
    long_description_content_type="text/markdown",
    python_requires=">=3.8",
    install_requires=["numpy"],
    packages=["ricci"],
    package_dir={"": "python"},
    # No sources: CMakeBuild builds it. Declared so that the wheel is tagged for this platform.
    ext_modules=[Extension("ricci._ricci", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    options={
        "build": {"build_base": os.path.join(_scratch, "build")},
        "egg_info": {"egg_base": _scratch},
    },
)
