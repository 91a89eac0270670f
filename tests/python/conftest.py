"""Shared fixtures of the Python module's tests: where svetlo, the scenes and a scratch folder
are. CTest runs them with PYTHONPATH=build/python and SVETLO=build/svetlo (tests/CMakeLists.txt)."""
import os
import struct

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture(scope="session")
def svetlo_bin():
    return os.environ.get("SVETLO", os.path.join(ROOT, "build", "svetlo"))


@pytest.fixture(scope="session")
def scenes():
    return os.path.join(ROOT, "scenes")


def read_pfm(path):
    """A little-endian RGB PFM as H x W x 3 float32, top row first (as svetlo's arrays)."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos].decode())
    pos += 1
    assert fields[0] == "PF" and float(fields[3]) < 0
    w, h = int(fields[1]), int(fields[2])
    a = np.frombuffer(data[pos:pos + w * h * 12], dtype="<f4").reshape(h, w, 3)
    return a[::-1].copy()
