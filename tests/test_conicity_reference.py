"""Rolling radius difference and equivalent conicity of S1002 on 60E1 at 1:40, against an independent computation.

No published Delta r(y) table or conicity value for S1002 / 60E1 (UIC 60) at 1:40 was reachable
(searched: the Manchester contact benchmark, the EN 15302 / UIC 519 reference cases, whose
profiles are other ones, theses and public repositories). The reference is therefore
:mod:`contact_geometry.reference`: the S1002 piecewise definition and the 60E1 head built from its
published arcs (``profiles/data/rail_heads.json``) evaluated exactly, the wheel lowered onto the rail
and the contact found as the largest ``z_rail + z_wheel`` on a 1 um lateral grid by ``argmax``.
The project's tables come from :func:`contact_geometry.study.study_geometry` (what the
``contact-geometry`` stage writes and ``pipeline.py geometry`` prints) with
``wheel.tread_profile = "S1002"``, ``rail.profile = "60E1"``, ``rail.inclination = 40``.

Tolerances (measured: see docs/verification.md):

* flange-back position: 1 um (the project reads the gauge point on the 0.25 mm outline polygon);
* Delta r on the 0.1 mm table, all 161 displacements of -8 ... +8 mm: 2 um while both wheels are on
  the tread (|y| < 5.1 mm; measured 0.3 um), 20 um when one flange root or face is in contact
  (measured 11 um at 6.6 mm, where the R13 flange root lies on the R13 rail corner: a nearly
  conformal contact whose position amplifies the 0.6 um chord error of the rail polygon);
* contact angle: 0.5 mrad on the tread, 3 mrad at the flange (measured 0.02 and 1.4 mrad);
* positions of the contact jumps of one wheel (tread 72 -> 62 mm from the flange back at
  y_w = 0.23 mm, flange root at 5.17 mm, flange face at 6.61 mm): 10 um (measured <= 1 um, the
  resolution of the search); the jumps lie between the same table samples in both;
* equivalent conicity at 3 mm, both by the harmonic linearisation of
  :mod:`contact_geometry.wheelset` (256 phases): 1e-3 (measured 1e-5). A Delta r error e changes it by
  at most (2/pi) e / A = 4e-4 for e = 2 um, A = 3 mm.
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_geometry.contact_search import contact_table
from contact_geometry.reference import (ExactRailHead, brute_force_contacts, brute_force_conicity, brute_force_dr)
from contact_geometry.study import study_geometry
from contact_geometry.wheelset import equivalent_conicity, rolling_radius_difference
from stages.config import load_study

SETTINGS = ('wheel.tread_profile="S1002"', 'rail.profile="60E1"', "rail.inclination=40")
Y = np.round(np.arange(-80, 81) * 1e-4, 10)  # -8 ... +8 mm by 0.1 mm
FLANGE_FROM = 5.1e-3  # |y| beyond which one wheel touches with its flange root or face (m)


@pytest.fixture(scope="module")
def project():
    return study_geometry(load_study(assignments=SETTINGS))


@pytest.fixture(scope="module")
def head():
    return ExactRailHead("60E1", 40)


def _on_grid(values, y, grid):
    """``values`` at the displacements ``grid`` (taken from the table's ``y``)."""
    idx = [int(np.flatnonzero(np.isclose(y, g, atol=1e-12))[0]) for g in grid]
    return np.asarray(values)[idx]


def _jumps(wheel_position, low=-8e-3, high=8e-3, coarse=1e-4, fine=1e-6, size=1e-3):
    """Displacements (m) where the contact position on the wheel jumps by more than ``size``
    between neighbours ``fine`` apart (bracketed on a ``coarse`` grid)."""
    y = np.linspace(low, high, int(round((high - low) / coarse)) + 1)
    w = wheel_position(y)
    out = []
    for i in np.flatnonzero(np.abs(np.diff(w)) > size):
        m = np.linspace(y[i], y[i + 1], int(round(coarse / fine)) + 1)
        d = np.abs(np.diff(wheel_position(m)))
        k = int(np.argmax(d))
        if d[k] > size:
            out.append(0.5 * (m[k] + m[k + 1]))
    return np.array(out)


def test_placement_matches(project, head):
    """The exact head's gauge point 14 mm below its top gives the project's flange-back position."""
    assert head.flange_back() == pytest.approx(project.pair.flange_back, abs=1e-6)
    assert project.pair.rail_tilt == pytest.approx(head.tilt, rel=1e-12)


def test_centred_contact_near_the_crown(head):
    """Issue 33: a centred S1002 wheelset on 60E1 at 1:40 touches near the crown, contact angle below 3 deg."""
    c = brute_force_contacts(head, [0.0])
    assert abs(c.y_rail[0]) < 0.005
    assert abs(c.contact_angle[0]) < np.radians(3.0)
    assert abs(c.y_wheel[0] - 0.070) < 0.005  # near the tape circle


def test_rolling_radius_difference_matches_brute_force(project, head):
    dr_project = _on_grid(project.dr, project.dr_displacement, Y)
    dr_brute = brute_force_dr(head, Y)
    err = np.abs(dr_project - dr_brute)
    tread = np.abs(Y) < FLANGE_FROM
    assert err[tread].max() < 2e-6, f"tread: max |ddr| {err[tread].max() * 1e6:.2f} um"
    assert err.max() < 20e-6, f"flange: max |ddr| {err.max() * 1e6:.2f} um at y = {Y[np.argmax(err)] * 1e3:.1f} mm"
    # the curve has the jumps and the flange climb it should have (not two equal wrong curves)
    assert 0.4e-3 < dr_brute[np.isclose(Y, 0.003)][0] < 1.5e-3
    assert dr_brute[-1] > 0.012 and np.allclose(dr_brute, -dr_brute[::-1])


def test_contact_angles_match(project, head):
    table = project.table
    brute = brute_force_contacts(head, Y)
    angle = _on_grid(table.contact_angle[:, 0], table.displacement, Y)
    err = np.abs(angle - brute.contact_angle)
    tread = np.abs(Y) < FLANGE_FROM
    assert err[tread].max() < 5e-4
    assert err.max() < 3e-3


def test_contact_jumps_at_the_same_displacements(project, head):
    pair = project.pair
    mine = _jumps(lambda y: contact_table(pair, y).y_wheel[:, 0])
    ref = _jumps(lambda y: brute_force_contacts(head, y).y_wheel)
    assert ref.size == 3, ref
    assert mine.size == ref.size, (mine, ref)
    assert np.abs(mine - ref).max() < 10e-6, (mine, ref)


def test_equivalent_conicity_matches(project, head):
    brute = brute_force_conicity(head, 0.003)
    assert project.conicity_amplitude == 0.003
    assert project.equivalent_conicity == pytest.approx(brute, abs=1e-3)
    assert 0.1 < brute < 0.3


@pytest.mark.slow
def test_dense_variant(project, head):
    """Half the lateral step (0.5 um), Delta r every 0.02 mm and the conicity from 0.5 to 8 mm."""
    y = np.round(np.arange(-400, 401) * 2e-5, 10)
    dr_project = rolling_radius_difference(project.pair, y)
    dr_brute = brute_force_dr(head, y, step=5e-7)
    jumps = _jumps(lambda v: brute_force_contacts(head, v, step=5e-7).y_wheel, fine=5e-7)
    near = np.zeros(y.size, bool)
    for j in jumps:  # a sample within 2 um of a jump may fall on either side in either model
        near |= (np.abs(y - j) < 2e-6) | (np.abs(-y - j) < 2e-6)
    err = np.abs(dr_project - dr_brute)[~near]
    tread = (np.abs(y) < FLANGE_FROM)[~near]
    assert err[tread].max() < 2e-6
    assert err.max() < 20e-6
    for amplitude in np.arange(0.5, 8.01, 0.5) * 1e-3:
        assert equivalent_conicity(project.pair, amplitude) == pytest.approx(
            brute_force_conicity(head, amplitude, step=5e-7), abs=1e-3), amplitude
