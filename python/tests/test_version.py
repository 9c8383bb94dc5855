"""ricci.__version__: the C++ library's version, which is CMake's project version."""

import pathlib
import re

import ricci


def test_version_is_the_cmake_project_version():
    cmake = (pathlib.Path(__file__).resolve().parents[2] / "CMakeLists.txt").read_text()
    expected = re.search(r"project\(\s*ricci\s+VERSION\s+([0-9][0-9.]*)", cmake).group(1)
    assert ricci.__version__ == expected
    assert ricci._ricci.__version__ == expected
