"""The stand-alone contact command: examples run, JSON fields, HDF5/PNG output, bad input."""

import json
import os
import re

import h5py
import pytest

from interaction.contact.cli import main

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                        "interaction", "contact", "examples")
FIELDS = ("Fn", "Fx", "Fy", "pmax", "n_contact", "n_stick", "n_slip")


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _example(name, tmp_path, **grid):
    """Copy an example, optionally with another [grid] (to keep the default run fast)."""
    text = open(os.path.join(EXAMPLES, name)).read()
    if grid:
        body = "".join(f"{k} = {v}\n" for k, v in grid.items())
        text = re.sub(r"\[grid\][^\[]*", "[grid]\n" + body + "\n", text)
    path = tmp_path / name
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("name,grid", [("steady.toml", {"nx": 24, "ny": 24}), ("transient.toml", {}),
                                       ("shift.toml", {}), ("point.toml", {})])
def test_examples_run_and_print_json(capsys, tmp_path, name, grid):
    code, out, err = _run(capsys, [_example(name, tmp_path, **grid), "--json"])
    assert code == 0, err
    data = json.loads(out)
    for key in FIELDS:
        assert key in data
    n = data["steps"]
    if n > 1:
        assert all(len(data[k]) == n for k in FIELDS)
    fn = data["Fn"][-1] if n > 1 else data["Fn"]
    assert fn > 0


@pytest.mark.slow
def test_steady_example_full_grid(capsys):
    code, out, err = _run(capsys, [os.path.join(EXAMPLES, "steady.toml"), "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["Fn"] == pytest.approx(82e3, rel=1e-9)
    assert abs(data["Fy"]) <= 0.3 * 82e3


def test_out_and_plot(capsys, tmp_path):
    h5 = tmp_path / "res.h5"
    png = tmp_path / "res.png"
    code, out, err = _run(capsys, [_example("shift.toml", tmp_path), "--out", str(h5), "--plot", str(png)])
    assert code == 0, err
    with h5py.File(h5) as f:
        assert f["pressure"].shape[0] == 4 and f["pressure"].attrs["units"] == "Pa"
        assert f["force"].attrs["units"] == "N" and f["x"].attrs["units"] == "m"
        assert f.attrs["schema"] == "contact"
    assert png.stat().st_size > 1000
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]


def test_point_model_plots_its_forces(capsys, tmp_path):
    # the point model has no traction fields: --plot draws the forces of its steps instead
    h5 = tmp_path / "point.h5"
    png = tmp_path / "point.png"
    code, out, err = _run(capsys, [_example("point.toml", tmp_path), "--out", str(h5), "--plot", str(png)])
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 1000
    with h5py.File(h5) as f:
        assert f["force"].shape == (20, 3)


BASE = """model = "halfspace"
kind = "steady"
[geometry]
semi_axes = [0.004, 0.003]
[material]
shear_modulus = 82e9
poisson_ratio = 0.28
[grid]
nx = 24
ny = 24
[load]
normal_force = 20e3
[friction]
coefficient = 0.3
[rolling]
creepage = [0.0, -1e-3, 0.0]
"""


@pytest.mark.parametrize("edit,field", [
    (("shear_modulus = 82e9", "shear_modulus = -82e9"), "material.shear_modulus"),
    (("coefficient = 0.3", "coefficient = -0.1"), "friction.coefficient"),
    (("nx = 24", "nx = 12"), "grid.nx"),
    (("normal_force = 20e3", "normal_force = 20e3\napproach = 1e-5"), "load"),
    (("[rolling]", "[rolling]\nsped = 3"), "rolling.sped"),
    (("poisson_ratio = 0.28", "poisson_ratio = 0.7"), "material.poisson_ratio"),
    (("model = \"halfspace\"", "model = \"fem\""), "model"),
    (("creepage = [0.0, -1e-3, 0.0]", "creepage = [0.0, -1e-3]"), "rolling.creepage"),
])
def test_bad_input_exits_2_naming_the_field(capsys, tmp_path, edit, field):
    path = tmp_path / "bad.toml"
    path.write_text(BASE.replace(*edit))
    code, out, err = _run(capsys, [str(path)])
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and f" {field}:" in lines[0]


def test_good_base_case_runs(capsys, tmp_path):
    # the unedited base of the bad-input cases is valid (so the failures above are the edits)
    path = tmp_path / "good.toml"
    path.write_text(BASE)
    code, out, err = _run(capsys, [str(path), "--json"])
    assert code == 0, err


def test_coarse_grid_by_element_size_keeps_the_contact_inside(capsys, tmp_path):
    # dx = dy = a / 2 gives a grid of the patch + 10 % plus one free element on each side, so the
    # contact does not reach the border elements (which the solver refuses)
    case = tmp_path / "coarse.toml"
    case.write_text('model = "halfspace"\nkind = "steady"\n[geometry]\nsemi_axes = [0.004, 0.004]\n'
                    '[grid]\ndx = 0.002\ndy = 0.002\n[load]\nnormal_force = 50e3\n[friction]\ncoefficient = 0.3\n'
                    '[rolling]\ncreepage = [0.0, -0.001, 0.0]\nspeed = 13.9\n')
    code, out, err = _run(capsys, [str(case), "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["Fn"] == pytest.approx(50e3, rel=1e-9)
    assert 0 < data["n_contact"] <= 25
