"""The examples run (examples/python): the two scripts in their quick form, and every code
cell of the notebook in order, as Jupyter would run them (from the notebook's folder), with
its outputs checked to be stripped."""
import json
import os
import subprocess
import sys

import svetlo
from conftest import ROOT

EXAMPLES = os.path.join(ROOT, "examples", "python")


def run_script(name, tmp_path):
    # The module the tests import, wherever PYTHONPATH pointed from.
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(svetlo.__file__)))
    out = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), "--quick", "-o",
                          str(tmp_path / "plot.png")], capture_output=True, text=True, timeout=300,
                         cwd=str(tmp_path), env=env)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_shadow_bias_sweep(tmp_path):
    out = run_script("shadow_bias_sweep.py", tmp_path)
    rows = [line.split() for line in out.splitlines()[1:] if line.strip()[:1].isdigit()]
    acne = [int(r[1]) for r in rows]
    peter = [int(r[2]) for r in rows]
    # The two sides of the trade-off: acne falls as the bias grows, peter-panning appears.
    assert acne[0] > acne[-1] and acne == sorted(acne, reverse=True), out
    assert peter[0] == 0 and peter[-1] > 0, out


def test_convergence(tmp_path):
    out = run_script("convergence.py", tmp_path)
    path = [float(line.split()[-1]) for line in out.split("radiosity")[0].splitlines()
            if "relMSE" in line]
    assert len(path) == 3 and path[0] > path[1] > path[2], out  # the path tracer converges


def test_notebook_runs_with_outputs_stripped(capsys):
    nb = json.load(open(os.path.join(EXAMPLES, "lighting.ipynb")))
    namespace = {}
    cwd = os.getcwd()
    os.chdir(EXAMPLES)
    try:
        for cell in nb["cells"]:
            if cell["cell_type"] != "code":
                continue
            assert cell["outputs"] == [] and cell["execution_count"] is None
            exec(compile("".join(cell["source"]), "lighting.ipynb", "exec"), namespace)
    finally:
        os.chdir(cwd)
    out = capsys.readouterr().out
    assert "refused:" in out and "total" in out
