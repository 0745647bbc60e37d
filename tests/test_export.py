"""Exports for users' tools: receptance and history CSV tables, VTU files (mode shapes, rail
waves, contact tractions) and XDMF sidecars, read back with the csv module and meshio and
compared with the HDF5 artefacts they come from."""

import csv
import math
import shutil
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np
import pytest

from stages import engine
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.params import Friction, Material
from contact.halfspace.tangential import SLIP, STICK
from interaction.simulate import simulate
from squealcore.errors import InputError
from stages.cases import make_case_id
from stages.config import load_study
from exports import (export_case, export_modes, export_rail, export_receptances,
                           write_traction_vtu, write_xdmf_sidecars)
from exports.case import case_structures, find_case
from stages.wheel import read_modes

STUDY = """
[time]
duration = 0.02

[contact]
grid_dy = 1e-3

[sweep]
"contact.friction" = [0.3]
"contact.lateral_creepage" = [-0.01]
"simulation.wheel_model" = ["stationary"]
"contact.model" = ["point", "halfspace"]
"""
POINT, HALFSPACE = (make_case_id({"contact.friction": 0.3, "contact.lateral_creepage": -0.01, "contact.model": model,
                                   "simulation.wheel_model": "stationary"}) for model in ("point", "halfspace"))


@pytest.fixture(scope="module")
def built(copy_quick_structures, tmp_path_factory):
    """The quick study (axisymmetric wheel) with its point-contact case, and the hex20 modes of
    the same wheel in a second folder."""
    root = tmp_path_factory.mktemp("export")
    config = root / "study.toml"
    config.write_text(STUDY)
    study = load_study(str(config), quick=True)
    out = copy_quick_structures(root / "out")  # the quick study's: fresh for this one
    assert engine.run_structural(study, out, engine.STAGES, progress=False) == []
    cases = [c for c in engine.plan_cases(study, out) if c.case_id == POINT]
    assert engine.run_cases(cases, out, progress=False) == ([POINT], {})
    hex_dir = root / "hex20"
    hex_dir.mkdir()
    shutil.copy2(out / "wheel_mesh.h5", hex_dir / "wheel_mesh.h5")
    hex_study = load_study(str(config), quick=True, assignments=["wheel.fe.solver=hex20"])
    assert engine.run(hex_study, hex_dir, until="wheel-modes", progress=False) == ["wheel-modes"]
    return {"study": study, "out": out, "hex": hex_dir, "root": root}


def read_csv(path):
    """(comment lines, column names, values (n, m)) of an exported CSV, parsed by numpy (correctly
    rounded decimal to binary64 conversion)."""
    with open(path, newline="") as handle:
        lines = handle.read().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    table = [line for line in lines if not line.startswith("#")]
    names = next(csv.reader(table[:1]))
    return comments, names, np.loadtxt(table[1:], delimiter=",", ndmin=2)


# ------------------------------------------------------------------------------ receptances
def test_receptance_tables_read_back_exactly(built, tmp_path):
    files = export_receptances(built["out"], tmp_path)
    assert sorted(p.name for p in files) == sorted(
        ["wheel_stationary_receptance.csv", "wheel_moving_load_receptance.csv", "wheel_eulerian_receptance.csv",
         "rail_point_receptance.csv", "rail_moving_receptance.csv"])
    expected = {}
    with h5py.File(built["out"] / "wheel_greens.h5") as f:
        for model in ("stationary", "moving_load", "eulerian"):
            expected[f"wheel_{model}_receptance.csv"] = (f["frequency"][()], f[model]["receptance"][()])
    with h5py.File(built["out"] / "rail_greens.h5") as f:
        assert f["distance"][0] == 0.0
        expected["rail_point_receptance.csv"] = (f["frequency"][()], f["receptance"][0])
        expected["rail_moving_receptance.csv"] = (f["moving/frequency"][()], f["moving/receptance"][()])
    for path in files:
        comments, names, values = read_csv(path)
        frequency, h = expected[path.name]
        assert any("H[i,j] = displacement i per unit force j" in line for line in comments)
        assert any("contact frame" in line for line in comments)
        assert names[0] == "frequency_Hz" and len(names) == 1 + 9 * 4
        column = {name: values[:, k] for k, name in enumerate(names)}
        # printed with repr: the round trip is exact
        assert np.array_equal(column["frequency_Hz"], frequency)
        for i, a in enumerate("xyz"):
            for j, b in enumerate("xyz"):
                assert np.array_equal(column[f"H_{a}{b}_re_m_per_N"], h[:, i, j].real), (path.name, a, b)
                assert np.array_equal(column[f"H_{a}{b}_im_m_per_N"], h[:, i, j].imag), (path.name, a, b)
                # level and phase from the printed real and imaginary parts (round-off of log10/atan2)
                z = column[f"H_{a}{b}_re_m_per_N"] + 1j * column[f"H_{a}{b}_im_m_per_N"]
                with np.errstate(divide="ignore"):
                    np.testing.assert_allclose(column[f"H_{a}{b}_dB_re_1m_per_N"], 20 * np.log10(np.abs(z)),
                                               rtol=1e-13)
                np.testing.assert_allclose(column[f"H_{a}{b}_phase_deg"], np.degrees(np.angle(z)), rtol=1e-13,
                                           atol=1e-12)


# ----------------------------------------------------------------------------------- modes
def test_mode_vtu_holds_the_hex20_shapes(built, tmp_path):
    path = tmp_path / "modes.vtu"
    assert export_modes(built["hex"], path, [1, 3]) == 2
    mesh = meshio.read(path)
    modes = read_modes(built["hex"] / "wheel_modes.h5", with_shapes=True)
    with h5py.File(built["hex"] / "wheel_mesh.h5") as f:
        np.testing.assert_array_equal(mesh.points, f["hex20/nodes"][()])
        np.testing.assert_array_equal(mesh.get_cells_type("hexahedron20"), f["hex20/cells"][()])
    names = sorted(mesh.point_data)
    assert [n[:8] for n in names] == ["mode_001", "mode_003"]
    np.testing.assert_array_equal(mesh.point_data[names[0]], modes["shapes"][0])
    np.testing.assert_array_equal(mesh.point_data[names[1]], modes["shapes"][2])


def test_axisymmetric_modes_expand_to_the_contact_shape(built, tmp_path):
    """The expanded 3D shape at the contact node (theta = 0, where the global and contact frames
    coincide) equals the contact shape the modal models use, for every mode."""
    path = tmp_path / "modes.vtu"
    modes = read_modes(built["out"] / "wheel_modes.h5")
    assert export_modes(built["out"], path) == modes["frequency"].size
    mesh = meshio.read(path)
    with h5py.File(built["out"] / "wheel_mesh.h5") as f:
        node = int(f["contact/hex_node"][()])
    for k, name in enumerate(sorted(mesh.point_data)):
        shape = modes["contact_shape"][k]
        # shapes are stored in single precision
        np.testing.assert_allclose(mesh.point_data[name][node], shape, atol=1e-6 * np.abs(shape).max())


@pytest.mark.parametrize("selection", [[0], [2, 10_000], []])
def test_out_of_range_modes_are_refused(built, tmp_path, selection):
    count = read_modes(built["out"] / "wheel_modes.h5")["frequency"].size
    path = tmp_path / "modes.vtu"
    with pytest.raises(InputError) as error:
        export_modes(built["out"], path, selection)
    assert error.value.field == "--modes" and f"1..{count}" in error.value.message
    assert not path.exists()


# ------------------------------------------------------------------------------------ rail
def test_rail_section_and_wave_shapes(built, tmp_path):
    with h5py.File(built["out"] / "rail_greens.h5") as f:
        grid, stored = f["frequency"][()], f["wavenumbers"][()]
    chosen = [int(np.argmin(np.abs(grid - f))) for f in (500.0, 2000.0)]
    files = export_rail(built["study"], built["out"], tmp_path, grid[chosen])
    assert [p.name for p in files] == ["rail_section.vtu", f"rail_waves_{grid[chosen[0]]:g}Hz.vtu",
                                       f"rail_waves_{grid[chosen[1]]:g}Hz.vtu", "rail_waves.csv"]
    with h5py.File(built["out"] / "rail_mesh.h5") as f:
        nodes, cells = f["section/nodes"][()], f["section/cells"][()]
    for path in files[:3]:
        mesh = meshio.read(path)
        np.testing.assert_array_equal(mesh.points, np.column_stack([np.zeros(len(nodes)), nodes]))
        np.testing.assert_array_equal(mesh.get_cells_type("quad8"), cells)
    _, names, table = read_csv(files[3])
    assert names == ["frequency_Hz", "wave_rank", "label_index", "kappa_re_rad_per_m", "kappa_im_rad_per_m",
                     "decay_dB_per_m"]
    for k, path in zip(chosen, files[1:3]):
        rows = table[table[:, 0] == grid[k]]
        kappa = rows[:, 3] + 1j * rows[:, 4]
        # the rail-greens stage's dispersion (same reduced model, sorted by decay the same way);
        # eigenvalue round-off of the two runs measured 7e-10
        np.testing.assert_allclose(kappa, stored[k][:len(kappa)], rtol=1e-8)
        np.testing.assert_allclose(rows[:, 5], -20 * np.log10(np.e) * kappa.imag, rtol=1e-12)
        mesh = meshio.read(path)
        shapes = {name[:-3]: mesh.point_data[name[:-3] + "_re"] + 1j * mesh.point_data[name[:-3] + "_im"]
                  for name in mesh.point_data}
        assert len(shapes) == len(rows)
        for name, u in shapes.items():
            assert np.abs(u).max() == pytest.approx(1.0, rel=1e-12)
        if grid[k] < 1000.0:
            # at 500 Hz the bending wavelength (~3 m) is far longer than the rail is high: the
            # least-decaying vertical wave moves the section rigidly up and down (measured 0.99)
            name, u = next((n, u) for n, u in sorted(shapes.items()) if "_vertical_" in n)
            rms = np.sqrt(np.mean(np.sum(np.abs(u) ** 2, axis=1)))
            assert abs(u[:, 2].mean()) / rms > 0.95


def test_rail_frequencies_are_checked(built, tmp_path):
    for bad in ([0.0], [-5.0], [math.inf], [], ["1000"]):
        with pytest.raises(InputError) as error:
            export_rail(built["study"], built["out"], tmp_path / "x", bad)
        assert error.value.field == "--frequencies"
    assert not (tmp_path / "x").exists()


# ------------------------------------------------------------------------------------ cases
def test_case_histories_read_back_exactly(built, tmp_path):
    files = export_case(built["study"], built["out"], POINT, tmp_path)
    assert [p.name for p in files] == [f"{POINT}_histories.csv"]
    comments, names, values = read_csv(files[0])
    assert any("rail on the wheel" in line for line in comments)
    column = {name: values[:, k] for k, name in enumerate(names)}
    with h5py.File(built["out"] / "cases" / f"{POINT}.h5") as f:
        assert np.array_equal(column["time_s"], f["time"][()])
        assert np.array_equal(column["slip_fraction_1"], f["slip_fraction"][()])
        for k, part in enumerate("xyz"):
            assert np.array_equal(column[f"force_{part}_N"], f["force"][:, k])
            for body in ("wheel", "rail"):
                assert np.array_equal(column[f"{body}_displacement_{part}_m"], f[f"{body}/displacement"][:, k])
                assert np.array_equal(column[f"{body}_velocity_{part}_m_per_s"], f[f"{body}/velocity"][:, k])
        for k, part in enumerate(("xi_1", "eta_1", "phi_1_per_m")):
            assert np.array_equal(column[f"creepage_{part}"], f["creepage"][:, k])


def test_point_contact_has_no_tractions_and_unknown_cases_are_refused(built, tmp_path):
    with pytest.raises(InputError) as error:
        export_case(built["study"], built["out"], POINT, tmp_path / "x", steps=[10])
    assert error.value.field == "--steps" and "halfspace" in error.value.message
    with pytest.raises(InputError) as error:
        export_case(built["study"], built["out"], "no_such_case", tmp_path / "x")
    assert error.value.field == "case" and POINT in error.value.message
    assert not (tmp_path / "x").exists()


def test_case_structures_reproduce_the_stored_history(built):
    """The re-run that gives the tractions rebuilds the case as the simulate stage did: same
    inputs, same code, so the same force history bit for bit."""
    _, cs = find_case(built["study"], POINT)
    wheel, rail, contact, kwargs = case_structures(cs, built["out"])
    with h5py.File(built["out"] / "cases" / f"{POINT}.h5") as f:
        stored = f["force"][()]
    result = simulate(wheel, rail, contact, n_steps=stored.shape[0], **kwargs)
    np.testing.assert_array_equal(result.force, stored)


def test_case_tractions_integrate_to_the_stored_forces(built, tmp_path):
    cases = [c for c in engine.plan_cases(built["study"], built["out"]) if c.case_id == HALFSPACE]
    assert engine.run_cases(cases, built["out"], progress=False) == ([HALFSPACE], {})
    steps = [100, 500]
    files = export_case(built["study"], built["out"], HALFSPACE, tmp_path, steps=steps)
    assert [p.name for p in files] == [f"{HALFSPACE}_histories.csv", f"{HALFSPACE}_tractions.vtu"]
    mesh = meshio.read(files[1])
    area = _cell_areas(mesh)
    with h5py.File(built["out"] / "cases" / f"{HALFSPACE}.h5") as f:
        force = f["force"][()]
    for step in steps:
        p = mesh.cell_data[f"step{step:07d}_pressure_Pa"][0]
        t = mesh.cell_data[f"step{step:07d}_traction_Pa"][0]
        assert (p * area).sum() == pytest.approx(force[step, 2], rel=1e-9)
        np.testing.assert_allclose((t[:, :2] * area[:, None]).sum(axis=0), force[step, :2], atol=1e-9 * 50e3)


def _cell_areas(mesh):
    """Areas (m^2) of the quads of a VTU, from their corner points (shoelace formula)."""
    quads = mesh.get_cells_type("quad")
    xy = mesh.points[quads][..., :2]
    x, y = xy[..., 0], xy[..., 1]
    return 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)


def test_traction_vtu_of_a_hertz_contact(tmp_path):
    """Fields of the half-space model on a small Hertz problem (a/b = 1.25, 50 kN): the pressure
    on the written cells integrates to the normal force, the tractions to the tangential force,
    and the stick/slip status comes back unchanged."""
    material = Material(80e9, 0.3)
    a, b, load = 5e-3, 4e-3, 50e3
    hertz = hertz_from_semi_axes(a, b, load, material.contact_modulus)
    grid = Grid.covering(a, b, nx=22, ny=18)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                             gap=hertz.A * x**2 + hertz.B * y**2, kind="steady", speed=20.0)
    results = {3: model.solve(model.initial_state(), normal_force=load, creepage=(0.0, -5e-4, 0.0)),
               7: model.solve(model.initial_state(), normal_force=load, creepage=(0.002, -0.02, 0.0))}
    path = write_traction_vtu({step: r.fields for step, r in results.items()}, tmp_path / "t.vtu")
    mesh = meshio.read(path)
    area = _cell_areas(mesh)
    np.testing.assert_allclose(area, grid.dx * grid.dy, rtol=1e-9)
    centres = mesh.points[mesh.get_cells_type("quad")].mean(axis=1)
    np.testing.assert_allclose(centres[:, 0], x.ravel(), atol=1e-12)
    np.testing.assert_allclose(centres[:, 1], y.ravel(), atol=1e-12)
    for step, result in results.items():
        p = mesh.cell_data[f"step{step:07d}_pressure_Pa"][0]
        t = mesh.cell_data[f"step{step:07d}_traction_Pa"][0]
        status = mesh.cell_data[f"step{step:07d}_status"][0]
        # the normal solver meets the prescribed load to its tolerance (1e-9)
        assert (p * area).sum() == pytest.approx(load, rel=1e-8)
        np.testing.assert_allclose((t[:, :2] * area[:, None]).sum(axis=0), result.force[:2], rtol=1e-12,
                                   atol=1e-12 * load)
        assert np.all(t[:, 2] == 0.0)
        np.testing.assert_array_equal(status, result.fields.status.ravel())
    assert {STICK, SLIP} <= set(mesh.cell_data["step0000003_status"][0].tolist())
    assert set(mesh.cell_data["step0000007_status"][0][mesh.cell_data["step0000007_pressure_Pa"][0] > 0]) == {SLIP}


# ------------------------------------------------------------------------------------- XDMF
def _resolve(item, folder, index=()):
    """Values of an XDMF ``DataItem``: an HDF reference or a hyperslab of one (meshio reads no
    hyperslabs), ``index`` a selection within it."""
    if item.get("ItemType") == "HyperSlab":
        selection, source = list(item)
        start, stride, count = np.array(selection.text.split(), dtype=int).reshape(3, -1)
        out = _resolve(source, folder, tuple(slice(s, s + c * d, d) for s, d, c in zip(start, stride, count)))
        assert out.shape == tuple(int(n) for n in item.get("Dimensions").split())
        return out
    assert item.get("Format") == "HDF"
    name, dataset = item.text.strip().split(":")
    with h5py.File(folder / name) as f:
        assert f[dataset].shape == tuple(int(n) for n in item.get("Dimensions").split())
        return f[dataset][index] if index else f[dataset][()]


def test_xdmf_sidecars_open_the_hdf5_fields(built):
    files = write_xdmf_sidecars(built["out"])
    # axisymmetric modes: no wheel_modes.xdmf (export modes writes them as VTU)
    assert sorted(p.name for p in files) == ["rail_mesh.xdmf", "wheel_mesh.xdmf"]
    wheel = meshio.read(built["out"] / "wheel_mesh.xdmf")
    with h5py.File(built["out"] / "wheel_mesh.h5") as f:
        nodes, cells = f["hex20/nodes"][()], f["hex20/cells"][()]
    np.testing.assert_array_equal(wheel.points, nodes)
    np.testing.assert_array_equal(wheel.get_cells_type("hexahedron20"), cells)
    # VTK / C3D20 order, which VTK's XDMF reader expects for Hexahedron_20 (it copies the
    # connectivity unchanged): the mid-edge nodes 8-19 lie on the edges 0-1, 1-2, 2-3, 3-0,
    # 4-5, ..., 3-7, each nearer to the middle of its own edge than to that of any other edge
    edges = np.array([(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6),
                      (3, 7)])
    middles = 0.5 * (nodes[cells[:, edges[:, 0]]] + nodes[cells[:, edges[:, 1]]])  # (E, 12, 3)
    distance = np.linalg.norm(nodes[cells[:, 8:]][:, :, None, :] - middles[:, None, :, :], axis=-1)
    np.testing.assert_array_equal(np.argmin(distance, axis=2), np.broadcast_to(np.arange(12), (len(cells), 12)))
    rail = meshio.read(built["out"] / "rail_mesh.xdmf")
    with h5py.File(built["out"] / "rail_mesh.h5") as f:
        np.testing.assert_array_equal(rail.points, f["section/nodes"][()])
        np.testing.assert_array_equal(rail.get_cells_type("quad8"), f["section/cells"][()])


def test_xdmf_mode_shapes_of_the_hex20_solver(built):
    files = write_xdmf_sidecars(built["hex"])
    assert sorted(p.name for p in files) == ["wheel_mesh.xdmf", "wheel_modes.xdmf"]
    path = built["hex"] / "wheel_modes.xdmf"
    modes = read_modes(built["hex"] / "wheel_modes.h5", with_shapes=True)
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == modes["frequency"].size
    with h5py.File(built["hex"] / "wheel_mesh.h5") as f:
        np.testing.assert_array_equal(points, f["hex20/nodes"][()])
        np.testing.assert_array_equal(cells[0].data, f["hex20/cells"][()])
    grids = ET.parse(path).getroot().find("Domain").find("Grid").findall("Grid")
    for k, grid in enumerate(grids):
        assert float(grid.find("Time").get("Value")) == k + 1
        assert grid.get("Name").startswith(f"mode_{k + 1:03d}_")
        values = {a.get("Name"): _resolve(a.find("DataItem"), built["hex"]) for a in grid.findall("Attribute")}
        np.testing.assert_array_equal(values["mode_shape"][0], modes["shapes"][k])
        assert values["frequency_Hz"][0] == modes["frequency"][k]
        assert values["nodal_diameters"][0] == modes["nodal_diameters"][k]
