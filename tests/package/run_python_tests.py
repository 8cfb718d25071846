"""Runs the Python module's tests (tests/python) against an installed loopsub wheel instead of a build tree.

The tests import the module as `_loopsub`, as the Blender add-on does; the wheel holds the same module as
loopsub._loopsub. Putting the installed package's folder first on sys.path makes the one the tests import the
wheel's. Used by cibuildwheel (.github/workflows/other-platforms.yml), run from outside the checkout.
Usage: python run_python_tests.py REPO [pytest arguments]
"""
import os
import sys

import loopsub
import pytest

repo = sys.argv[1]
sys.path.insert(0, os.path.dirname(loopsub.__file__))
import _loopsub  # noqa: E402

print(f"testing {_loopsub.__file__} (best kernel {_loopsub.best_kernel()})")
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", os.path.join(repo, "tests", "python")] + sys.argv[2:]))
