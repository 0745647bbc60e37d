"""The table of normal solutions that warm-starts the compiled time loop (HalfspaceContact.normal_table)."""

import numpy as np

from contact.halfspace import model as halfspace
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.halfspace.normal import solve_normal
from contact.params import Friction, Material


def _model(a=5e-3, b=4e-3, tol=1e-9, nx=16, ny=14):
    material = Material(80e9, 0.3)
    hz = hertz_from_semi_axes(a, b, 50e3, material.contact_modulus)
    grid = Grid.covering(a, b, nx=nx, ny=ny)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    return HalfspaceContact(material=material, friction=Friction(0.3), grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                            kind="transient", speed=20.0, tol=tol)


def test_table_entries_are_normal_solutions_at_their_approaches():
    # Each entry against the stand-alone normal solver at the same approach (its own CG from a
    # cold start): pressures to 1e-6 of the peak (both stop at tolerance 1e-9 on the relative
    # pressure change, from different starts), force the sum of the pressure times the area.
    model = _model()
    table = model.normal_table(entries=64)
    assert np.all(np.diff(table.approach) > 0) and np.all(np.diff(table.force) > 0)
    area = model.grid.dx * model.grid.dy
    for k in (0, 20, 63):
        reference = solve_normal(model.kernels, model.gap, approach=table.approach[k], tol=1e-9)
        pressure = table.pressure[k].reshape(model.grid.nx, model.grid.ny)
        assert np.abs(pressure - reference.pressure).max() <= 1e-6 * reference.pressure.max()
        assert np.isclose(table.force[k], pressure.sum() * area, rtol=1e-12)


def test_table_is_computed_once_per_contact_and_process(monkeypatch):
    # The same contact alone (coefficients, gap, tolerance) reuses the table: the same arrays,
    # no second computation; another gap or tolerance gets its own; at most NORMAL_TABLES_KEPT
    # are kept (the least recently used goes).
    calls = []
    real = halfspace.normal_solution_table

    def counting(*args):
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(halfspace, "normal_solution_table", counting)
    monkeypatch.setattr(halfspace, "_normal_tables", type(halfspace._normal_tables)())
    first = _model().normal_table(entries=32)
    again = _model().normal_table(entries=32)  # another model object, the same contact
    assert again is first and len(calls) == 1
    wider = _model(a=6e-3).normal_table(entries=32)
    looser = _model(tol=1e-6).normal_table(entries=32)
    assert len(calls) == 3 and wider is not first and looser is not first
    assert not np.array_equal(wider.pressure, first.pressure)
    assert len(halfspace._normal_tables) == halfspace.NORMAL_TABLES_KEPT == 2
    recomputed = _model().normal_table(entries=32)  # evicted by the two others: computed again
    assert len(calls) == 4 and np.array_equal(recomputed.pressure, first.pressure)
