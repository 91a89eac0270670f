"""Shared fixtures of the Python module's tests: where svetlo, the scenes and a scratch folder
are. CTest runs them with PYTHONPATH=build/python and SVETLO=build/svetlo (tests/CMakeLists.txt)."""
import os
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "app"))
import pfm_tool  # noqa: E402  (the shell tests' PFM reader)


@pytest.fixture(scope="session")
def svetlo_bin():
    return os.environ.get("SVETLO", os.path.join(ROOT, "build", "svetlo"))


@pytest.fixture(scope="session")
def scenes():
    return os.path.join(ROOT, "scenes")


def read_pfm(path):
    """A little-endian RGB PFM as H x W x 3 float32, top row first (as svetlo's arrays), read by
    tests/app/pfm_tool.py."""
    w, h, rows = pfm_tool.read(path)
    return np.array(rows, dtype=np.float32).reshape(h, w, 3)
