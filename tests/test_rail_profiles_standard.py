"""Issue 33 (items 1 and 3, partly): the published 60E1 head and the contact geometry on it.

Published figures (sources in mesh/data/rail_heads.json and docs/user-guide.md, Profiles):
60E1 head R300 / R80 / R13 with tangent points at half-widths 10.228, 26.0265 and 36.000 mm and
flanks 1:20 (GENSYS KPF manual, 'Creation of a rail profile from a drawing'); section area
7670 mm^2, 60.21 kg/m, I_vertical 3038 cm^4, I_lateral 512.3 cm^4 (British Steel EN 13674-1
section table).
"""

import math

import numpy as np
import pytest

from contact_geometry.contact_search import WheelRailPair, contact_table
from contact_geometry.rail_profiles import gauge_point, inclined_outline, rail_head_profile
from contact_geometry.track import flange_back_position
from contact_geometry.wheel_profiles import s1002_profile
from mesh.rail_mesh import mesh_rail_section
from mesh.rail_section import ALIASES, HEADS, PROFILES, RailParams, head_arcs, polygon_area, rail_outline
from mesh.s1002 import s1002_height
from squealcore.errors import InputError
from waveguide.section import section_properties

H = 0.172
R0 = 0.46


@pytest.fixture(scope="module")
def props():
    return section_properties(mesh_rail_section(RailParams(profile="60E1", element_size=0.004)), 7850.0)


def _circle_fit(p):
    """Least-squares circle (centre, radius) through points p (n, 2)."""
    a = np.column_stack([2 * p, np.ones(len(p))])
    b = np.sum(p**2, axis=1)
    cy, cz, c = np.linalg.lstsq(a, b, rcond=None)[0]
    return np.array([cy, cz]), math.sqrt(c + cy**2 + cz**2)


def test_60e1_head_radii_and_tangent_points():
    head = HEADS["60E1"]
    g = head_arcs(head, H)
    t = g["tangents"]
    # the published tangent-point half-widths, to 0.05 mm
    np.testing.assert_allclose(t[:, 0] * 1e3, [10.228, 26.0265, 36.0], atol=0.05)
    # the crown centre on the axis, 300 mm below the top
    np.testing.assert_allclose(g["centres"][0] * 1e3, [0.0, 172.0 - 300.0], atol=1e-9)
    # radii of the dense outline between the tangent points, fitted, to 0.05 mm
    out = rail_outline("60E1", size=2e-5)
    field = out[(out[:, 0] >= 0) & (out[:, 1] > H - 0.02)]
    pieces = [(0.0, t[0, 0], 0.300), (t[0, 0], t[1, 0], 0.080)]
    for y0, y1, r in pieces:
        p = field[(field[:, 0] > y0 + 1e-4) & (field[:, 0] < y1 - 1e-4)]
        assert _circle_fit(p)[1] == pytest.approx(r, abs=5e-5)
    corner = field[(field[:, 0] > t[1, 0] + 1e-4) & (field[:, 1] > t[2, 1] + 1e-4)]
    assert _circle_fit(corner)[1] == pytest.approx(0.013, abs=5e-5)
    # the corner tangent point lies 14.30 mm below the top (derived from the published points)
    assert (H - t[2, 1]) * 1e3 == pytest.approx(14.30, abs=0.05)


def test_60e1_head_is_tangent_continuous():
    """No kink between crown, shoulder, corner and flank: the published tangent points make the
    arcs tangent by construction except the corner/flank joint, where the published half-width
    36.000 mm leaves the corner arc's end 0.017 deg off the 1:20 flank; allowed 0.05 deg."""
    g = head_arcs(HEADS["60E1"], H)
    c, t = g["centres"], g["tangents"]
    for i in range(2):  # consecutive arcs: centres and the tangent point on one line
        u = (t[i] - c[i]) / np.linalg.norm(t[i] - c[i])
        v = (t[i] - c[i + 1]) / np.linalg.norm(t[i] - c[i + 1])
        assert math.degrees(math.acos(min(1.0, float(u @ v)))) < 1e-6
    normal = (t[2] - c[2]) / np.linalg.norm(t[2] - c[2])
    flank_normal = np.array([1.0, 1.0 / 20.0]) / math.hypot(1.0, 1.0 / 20.0)  # flank widens downwards
    assert math.degrees(math.acos(float(normal @ flank_normal))) < 0.05
    # along the dense outline of the head (top to the flank's end) the direction turns
    # smoothly: no turn between neighbouring chords larger than the arc sampling's own turn
    size = 2.5e-4
    out = rail_outline("60E1", size=size)
    head = out[(out[:, 0] >= -1e-12) & (out[:, 1] > H - 0.03)]
    head = head[np.argsort(-head[:, 1])]
    d = np.diff(head, axis=0)
    ang = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    assert np.max(np.abs(np.diff(ang))) < size / 0.013 + math.radians(0.05)


def test_60e1_area_mass_and_bending(props):
    # published 7670 mm^2 and 60.21 kg/m within 0.5 %
    assert props.area == pytest.approx(7670e-6, rel=0.005)
    assert props.mass_per_length == pytest.approx(60.21, rel=0.005)
    # vertical bending: 3038 cm^4 published; the body below the head is still parametric (no
    # reachable drawing), the head is the published one: within 2 %
    assert props.i_vertical == pytest.approx(3038e-8, rel=0.02)


@pytest.mark.xfail(strict=True, reason="body below the head parametric: I_lateral 564 cm^4 vs "
                                       "published 512.3 (+10 %); needs the 60E1 web/foot drawing")
def test_60e1_lateral_bending_published(props):
    assert props.i_lateral == pytest.approx(512.3e-8, rel=0.02)


def test_aliases_and_names():
    assert ALIASES == {"UIC60": "60E1"}
    np.testing.assert_array_equal(rail_outline("UIC60"), rail_outline("60E1"))
    RailParams.from_mapping({"profile": "UIC60"}).cross_check()
    with pytest.raises(InputError) as e:
        RailParams.from_mapping({"profile": "UIC54"}).cross_check()
    assert e.value.field == "rail.profile"
    for name in (*PROFILES, *ALIASES):
        assert name in e.value.message
    assert polygon_area(rail_outline("BV50")) > 0  # BV50 unchanged (parametric head)


def _pair(n):
    fb = flange_back_position(gauge_point("60E1", n))
    return WheelRailPair(s1002_profile(), rail_head_profile("60E1", n), R0, fb, math.atan(1 / n))


@pytest.mark.parametrize("n", [40, 20])
def test_s1002_on_60e1_centred_contacts_the_crown(n):
    t = contact_table(_pair(n), [0.0])
    assert abs(t.contact_angle[0, 0]) < math.radians(3.0)
    assert abs(t.y_rail[0, 0]) < 0.0125  # within the crown and shoulder of the head (26 mm wide R80 start)
    if n == 40:  # the profile pair S1002 / 60E1 was designed for 1:40: near the tape circle
        assert t.y_wheel[0, 0] == pytest.approx(0.070, abs=0.005)
    else:  # at 1:20 the tread contact moves towards the field side but stays on the tread
        assert 0.070 < t.y_wheel[0, 0] < 0.095


@pytest.mark.parametrize("n", [40, 20])
def test_flange_contact_within_the_flangeway_clearance(n):
    """S1002 wheelset on standard gauge: 5 mm of flangeway clearance at the flange-thickness
    height; with the flange root's rounding the flange contact (angle > 1 rad) starts a little
    beyond, between 4 and 8 mm."""
    d = np.arange(0.0, 0.010, 1e-4)
    t = contact_table(_pair(n), d)
    flange = d[np.argmax(t.contact_angle[:, 0] > 1.0)]
    assert 0.004 <= flange <= 0.008
    # (on the way the 1:40 contact jumps from the crown to the shoulder near 0.3 mm, 0.064
    # rad, and climbs the gauge corner, 0.3 rad, before the flange takes it)


def _analytic_head_height(y, n):
    """Height (m) of the 60E1 head inclined 1:n at lateral position y, from the exact arcs:
    the upright head's points are rotated and the surface height is found at each y."""
    g = head_arcs(HEADS["60E1"], H)
    c, t, ang = g["centres"], g["tangents"], g["angles"]
    radii = (0.300, 0.080, 0.013)
    pts = []
    for i, (a0, a1) in enumerate(((ang[0], np.pi - ang[0]), (ang[1], ang[0]), (ang[2], ang[1]))):
        a = np.linspace(a0, a1, 200001) if i == 0 else np.linspace(a0, a1, 200001)
        p = np.column_stack([c[i, 0] + radii[i] * np.cos(a), c[i, 1] + radii[i] * np.sin(a)])
        pts.append(p)
        pts.append(p * [-1, 1])
    p = np.vstack(pts)
    alpha = math.atan(1.0 / n)
    rot = np.array([[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]])
    q = (p - [0.0, H]) @ rot.T + [0.0, H]
    order = np.argsort(q[:, 0])
    return np.interp(y, q[order, 0], q[order, 1])


def test_contact_point_against_brute_force_on_the_exact_arcs():
    """Independent check of the 1:40 centred contact: the exact arcs (not the outline polygon
    nor its spline) and the analytic S1002 pieces, the gap minimised on a 1 um grid. The
    published Manchester-benchmark reference (Delta r(y), contact angles) was not reachable."""
    n = 40
    pair = _pair(n)
    t = contact_table(pair, [0.0])
    y = np.arange(-0.02, 0.02, 1e-6)
    s = (y - pair.flange_back) * 1e3 - 70.0  # S1002 coordinate from the tape circle (mm)
    f = _analytic_head_height(y, n) + s1002_height(s) * 1e-3
    k = int(np.argmax(f))
    assert t.y_rail[0, 0] == pytest.approx(y[k], abs=2e-4)
    slope = (f[k + 50] - f[k - 50]) / 1e-4  # ~0 at the maximum: smooth contact
    assert abs(slope) < 1e-3
    zr = _analytic_head_height(y[k - 5:k + 6], n)
    angle = math.atan((zr[-1] - zr[0]) / 1e-5)
    assert t.contact_angle[0, 0] == pytest.approx(angle, abs=1e-3)
    # the outline the contact uses follows the exact arcs to within the chord sag (0.25 mm
    # chords on R13: 0.6 um)
    head = rail_head_profile("60E1", n)
    yy = np.linspace(-0.03, 0.03, 601)
    assert np.max(np.abs(head.height(yy) - _analytic_head_height(yy, n))) < 2e-6


def test_inclined_head_matches_outline():
    out = inclined_outline("60E1", 40)
    assert out[:, 1].max() == pytest.approx(H, abs=1e-4)
