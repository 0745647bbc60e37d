"""The stand-alone contact command: examples run, JSON fields, HDF5/PNG output, bad input."""

import json
import os
import re

import h5py
import pytest

from contact.cli import main

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                        "contact", "examples")
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
    (("nx = 24\nny = 24", "nx = 2000\nny = 2000"), "grid"),  # 4e6 elements: refused before any allocation
    (("semi_axes = [0.004, 0.003]", 'gap_file = "/dev/zero"'), "geometry.gap_file"),  # a device never ends
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


def test_every_key_but_model_has_a_default(capsys, tmp_path):
    # the defaults are the default study's contact (curvatures from r0 = 0.39 m and the 0.3 m rail
    # head, load 50 kN), so a case that states only what differs from them (material, rolling)
    # gives the same numbers as point.toml, which writes the geometry and the load out
    minimal = tmp_path / "minimal.toml"
    minimal.write_text('model = "point"\nkind = "transient"\n[material]\nyoung_modulus = 210e9\npoisson_ratio = 0.3\n'
                       '[rolling]\ncreepage = [0.0, -0.005, 0.0]\nspeed = 13.888888888888889\nsteps = 20\n'
                       'time_step = 3.6e-5\n')
    code, out, err = _run(capsys, [str(minimal), "--json"])
    assert code == 0, err
    code, ref, err = _run(capsys, [os.path.join(EXAMPLES, "point.toml"), "--json"])
    assert code == 0, err
    got, expected = json.loads(out), json.loads(ref)
    assert set(got) == set(expected)
    for key in FIELDS:  # the same up to the rounding of the curvatures written in point.toml
        assert got[key] == pytest.approx(expected[key], rel=1e-12, abs=1e-9), key
    # the model alone is a complete case
    only = tmp_path / "only.toml"
    only.write_text('model = "halfspace"\n')
    code, out, err = _run(capsys, [str(only), "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["Fn"] == pytest.approx(50e3, rel=1e-9) and data["hertz"]["normal_force"] == 50e3
    # Hertz semi-axes of the default geometry against the point.toml run's (same curvatures and load,
    # but G = 82 GPa, nu = 0.28 here: a, b scale as (1 / E*)^(1/3))
    e_star_here = 82e9 / (1 - 0.28)
    e_star_ref = 210e9 / (2 * 1.3) / (1 - 0.3)
    scale = (e_star_ref / e_star_here) ** (1 / 3)
    assert data["hertz"]["a"] == pytest.approx(json.loads(ref)["hertz"]["a"] * scale, rel=1e-12)
    assert data["hertz"]["b"] == pytest.approx(json.loads(ref)["hertz"]["b"] * scale, rel=1e-12)


@pytest.mark.parametrize("edit,field", [
    (("coefficient = 0.3", "coefficient = inf"), "friction.coefficient"),
    (("coefficient = 0.3", "coefficient = 0.0"), "friction.coefficient"),
    (("coefficient = 0.3", "coefficient = nan"), "friction.coefficient"),
    (("normal_force = 20e3", "normal_force = inf"), "load.normal_force"),
    (("shear_modulus = 82e9", "shear_modulus = inf"), "material.shear_modulus"),
    (("semi_axes = [0.004, 0.003]", "semi_axes = [0.004, inf]"), "geometry.semi_axes"),
    (("semi_axes = [0.004, 0.003]", "semi_axes = [0.004, 0.003]\ncurvatures = [1.0, 1.0]"), "geometry"),
    (("creepage = [0.0, -1e-3, 0.0]", "creepage = [0.0, -1e-3, nan]"), "rolling.creepage"),
    (("[rolling]", "[rolling]\nspeed = -inf"), "rolling.speed"),
    (("[rolling]", "[rolling]\nsteps = 2.5"), "rolling.steps"),
    (("nx = 24", "nx = inf"), "grid.nx"),
    (("model = \"halfspace\"\n", ""), "model"),
    (("kind = \"steady\"", "kind = \"steady\"\ncolour = \"red\""), "colour"),
])
def test_non_finite_and_meaningless_values_exit_2_naming_the_field(capsys, tmp_path, edit, field):
    path = tmp_path / "bad.toml"
    path.write_text(BASE.replace(*edit))
    code, out, err = _run(capsys, [str(path)])
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and f" {field}:" in lines[0] and "must" in lines[0], lines


@pytest.mark.parametrize("make", ["directory", "binary", "missing"])
def test_unreadable_case_files_exit_2_naming_the_file(capsys, tmp_path, make):
    path = tmp_path / "case.toml"
    if make == "directory":
        path.mkdir()
    elif make == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    code, out, err = _run(capsys, [str(path)])
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and "Traceback" not in err


def test_plot_format_follows_the_extension(capsys, tmp_path):
    case = _example("shift.toml", tmp_path)
    pdf = tmp_path / "fields.pdf"
    code, out, err = _run(capsys, [case, "--plot", str(pdf)])
    assert code == 0, err
    assert pdf.read_bytes()[:5] == b"%PDF-"
    # an extension matplotlib cannot write is refused before solving: nothing is written
    before = sorted(os.listdir(tmp_path))
    for name in ("fields.xyz", "fields"):
        code, out, err = _run(capsys, [case, "--plot", str(tmp_path / name), "--out", str(tmp_path / "r.h5")])
        assert code == 2 and out == "" and " --plot:" in err and ".png" in err
    assert sorted(os.listdir(tmp_path)) == before


def test_out_is_an_artefact_with_the_resolved_case(capsys, tmp_path):
    from squealcore.artefacts import params_hash

    h5 = tmp_path / "res.h5"
    code, out, err = _run(capsys, [_example("point.toml", tmp_path), "--out", str(h5)])
    assert code == 0, err
    with h5py.File(h5) as f:
        config = json.loads(f.attrs["config"])
        assert f.attrs["params_sha256"] == params_hash(config)
        assert f.attrs["complete"] and f.attrs["schema"] == "contact"
    # the resolved case: the file's values and the defaults of the keys it leaves out
    assert config["model"] == "point" and config["friction"] == {"coefficient": 0.3, "characteristic": "constant",
                                                             "slope": 0.0}
    assert config["rolling"]["steps"] == 20 and config["shift"] == {"displacement": [0.0, 0.0, 0.0]}


def test_add_args_and_run_command_wire_the_command_into_another_parser(capsys, tmp_path):
    import argparse

    from contact.cli import add_args, run_command

    parser = argparse.ArgumentParser(prog="pipeline.py")
    sub = parser.add_subparsers(dest="command")
    add_args(sub.add_parser("contact"))
    args = parser.parse_args(["contact", _example("point.toml", tmp_path), "--json"])
    assert run_command(args) == 0
    assert json.loads(capsys.readouterr().out)["steps"] == 20


def _grid_case(tmp_path, grid, kind="steady", steps=1):
    case = tmp_path / "grid.toml"
    case.write_text(f'model = "halfspace"\nkind = "{kind}"\n[geometry]\nsemi_axes = [0.005, 0.004]\n'
                    f'[material]\nshear_modulus = 80e9\npoisson_ratio = 0.3\n[grid]\n{grid}\n'
                    '[load]\nnormal_force = 50e3\n[friction]\ncoefficient = 0.3\n'
                    f'[rolling]\ncreepage = [0.0, -0.003, 0.0]\nspeed = 20.0\nsteps = {steps}\n')
    return str(case)


def test_grid_of_22_by_18_at_the_patch_plus_10_percent_is_accepted(capsys, tmp_path):
    # issue 16: the grid 22 x 18 over 1.1 times the patch was refused (one free border element
    # exactly, lost to round-off)
    code, out, err = _run(capsys, [_grid_case(tmp_path, "nx = 22\nny = 18"), "--json"])
    assert code == 0, err
    assert json.loads(out)["Fn"] == pytest.approx(50e3, rel=1e-9)


@pytest.mark.parametrize("kind", ["steady", "transient"])
def test_explicit_grid_touching_the_contact_warns_and_solves(capsys, tmp_path, caplog, kind):
    # grid.extent = the Hertz patch itself, 20 x 16 elements: the border elements are in contact;
    # the case runs (as CONTACT would), with a WARNING that gives the numbers
    with caplog.at_level("WARNING", logger="contact"):
        code, out, err = _run(capsys, [_grid_case(tmp_path, "extent = [0.010, 0.008]\nnx = 20\nny = 16", kind,
                                                  steps=3 if kind == "transient" else 1), "--json"])
    assert code == 0, err
    data = json.loads(out)
    fn = data["Fn"] if kind == "steady" else data["Fn"][-1]
    assert fn == pytest.approx(50e3, rel=1e-9)
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert any("reaches the edge of the 20 x 16 grid (0.01 x 0.008 m)" in w and "leading" in w for w in warnings)


@pytest.mark.parametrize("option", ["--out", "--plot"])
def test_output_naming_a_folder_is_refused_before_solving(capsys, tmp_path, option):
    """--out / --plot naming an existing folder: exit 2 naming the option, nothing solved (no result printed)."""
    case = _example("point.toml", tmp_path)
    code, out, err = _run(capsys, [case, option, str(tmp_path)])
    assert code == 2
    assert err.strip().splitlines()[0].startswith(f"error: {option}: must name a file")
    assert out == ""


def test_grid_coarser_than_the_contact_warns_with_the_numbers(capsys, tmp_path, caplog):
    """dx = 3 mm on a = 5 mm (1.7 elements per semi-axis): solved as asked, with a WARNING; 0.5 mm: none."""
    with caplog.at_level("WARNING", logger="contact"):
        code, out, err = _run(capsys, [_grid_case(tmp_path, "dx = 0.003\ndy = 0.0005", "steady"), "--json"])
    assert code == 0, err
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert any("grid.dx = 0.003 m resolves the contact's semi-axis a = 0.005 m by 1.67 elements" in w
               for w in warnings), warnings
    assert not any("grid.dy" in w for w in warnings)
    caplog.clear()
    with caplog.at_level("WARNING", logger="contact"):
        code, out, err = _run(capsys, [_grid_case(tmp_path, "dx = 0.0005\ndy = 0.0005", "steady"), "--json"])
    assert code == 0, err
    assert not any("resolves the contact" in r.getMessage() for r in caplog.records)


@pytest.mark.parametrize("grid,field", [("extent = [0.010, 0.008]\nnx = 20", "grid.ny"),
                                        ("extent = [0.010, 0.008]\nnx = 20\ndy = 0.0003", "grid.dy"),
                                        ("extent = [0.010, 0.008]\nnx = 20\nny = 16\ndx = 0.001", "grid.dx")])
def test_explicit_grid_bad_input_names_the_field(capsys, tmp_path, grid, field):
    code, out, err = _run(capsys, [_grid_case(tmp_path, grid)])
    assert code == 2
    assert f" {field}:" in err.strip().splitlines()[0]


def test_several_case_files_are_solved_in_one_process(capsys, tmp_path):
    """Each case of a batch gives the numbers it gives alone (the order and the shared kernels change nothing)."""
    point = _example("point.toml", tmp_path)
    shift = _example("shift.toml", tmp_path)
    alone = []
    for path in (point, shift):
        code, out, err = _run(capsys, [path, "--json"])
        assert code == 0, err
        alone.append(json.loads(out))
    code, out, err = _run(capsys, [shift, point, "--json"])
    assert code == 0, err
    batch = json.loads(out)
    assert [entry["case"] for entry in batch] == [shift, point]
    for entry, single in zip(batch, alone[::-1]):
        assert {k: v for k, v in entry.items() if k != "case"} == single
    code, out, err = _run(capsys, [point, shift])  # text: one line per case, named
    assert code == 0, err
    lines = out.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith(point + ": ") and lines[1].startswith(shift + ": ")


def test_a_bad_case_in_a_batch_stops_it_before_anything_is_solved(capsys, tmp_path):
    point = _example("point.toml", tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_text(open(point).read().replace("[friction]", "[friction]\ncoefficient_typo = 1\n"))
    code, out, err = _run(capsys, [point, str(bad), "--json"])
    assert code == 2
    assert out == ""  # the good first case was not solved either
    assert err.startswith("error: ") and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("option,value", [("--out", "f.h5"), ("--plot", "f.png")])
def test_field_output_of_a_batch_is_refused(capsys, tmp_path, option, value):
    point = _example("point.toml", tmp_path)
    code, out, err = _run(capsys, [point, point, option, str(tmp_path / value)])
    assert code == 2
    assert err.startswith(f"error: {option}: ") and "one case file" in err
    assert not (tmp_path / value).exists()
