#!/usr/bin/env bash
# `pip install --no-build-isolation .` (docs/python.md) into a fresh virtual environment that
# sees Debian's packages (numpy, setuptools), with no index: nothing may come from PyPI. The
# installed module must render what the one in build/python renders, bit for bit.
# Usage: pip_install_test.sh PYTHON SOURCE_DIR BUILD_PYTHON_DIR
set -euo pipefail
python=$1
source_dir=$2
built=$3
work=$(mktemp -d)
trap 'rm -rf "$work" "$source_dir/svetlo.egg-info"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --quiet --no-build-isolation --no-index "$source_dir"
cd "$work"
scene="$source_dir/scenes/cornell.json"
"$work/venv/bin/python" -c "
import numpy as np, svetlo
assert svetlo.__file__.startswith('$work/venv'), svetlo.__file__
np.save('installed.npy', svetlo.render('$scene', engine='path', spp=2, width=24, height=16).image)"
PYTHONPATH="$built" "$python" -c "
import numpy as np, svetlo
assert np.array_equal(np.load('installed.npy'),
                      svetlo.render('$scene', engine='path', spp=2, width=24, height=16).image)"
echo "pip install: the installed module renders as build/python's"
