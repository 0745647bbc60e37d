"""Issue 33 (items 1 and 3, partly): the published 60E1 head, the 54E1 section and the contact
geometry on them.

Published figures (sources in profiles/data/rail_heads.json and docs/user-guide.md, Profiles):
60E1 head R300 / R80 / R13 with tangent points at half-widths 10.228, 26.0265 and 36.000 mm and
flanks 1:20 (GENSYS KPF manual, 'Creation of a rail profile from a drawing'); section figures
from the British Steel EN 13674-1 table (as transcribed in github.com/xcfem/xc): 60E1 7670 mm^2,
60.21 kg/m, I_vertical 3038 cm^4, I_lateral 512.3 cm^4, centroid 80.9 mm above the foot; 54E1
6977 mm^2, 54.77 kg/m, 2338 / 419.2 cm^4, centroid 75.1 mm, head width 70 mm. The 54E1 head
arcs are ASSUMED equal to 60E1's (no reachable source), their tangent points derived.
"""

import math

import numpy as np
import pytest

from contact_geometry.contact_search import WheelRailPair, contact_table
from contact_geometry.track import flange_back_position
from mesh.rail_mesh import mesh_rail_section
from profiles.rail_head import gauge_point, inclined_outline, rail_head_profile
from profiles.rail_section import (ALIASES, HEADS, PROFILES, RailParams, head_arcs, polygon_area, rail_outline,
                               shoulder_end_by_tangency)
from profiles.s1002 import s1002_height
from profiles.wheel_treads import s1002_profile
from squealcore.errors import InputError
from waveguide.section import section_properties

H = 0.172
R0 = 0.46


def _props(name):
    return section_properties(mesh_rail_section(RailParams(profile=name, element_size=0.004)), 7850.0)


@pytest.fixture(scope="module")
def props():
    return _props("60E1")


@pytest.fixture(scope="module")
def props54():
    return _props("54E1")


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
    out = rail_outline("60E1", size=2e-4)
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


# Tolerances of the section figures. Area and mass: 0.5 % (issue 33). Second moments: 2 %. The
# body below the head is not drawn from a published drawing (none reachable): its four free
# dimensions (fishing-surface slope, fillet radius, foot-edge and foot-root heights) were fitted,
# in 0.1 mm steps, to the four published figures (area, both second moments, centroid height) on
# the exact outline; the fit with rounded dimensions is within 0.07 %, the 4 mm quad8 mesh used
# here adds < 0.1 %, the published figures carry 4 digits (0.05 %). So these tests guard the
# outline, the mesh and the section-property integration against drift, not an independent
# prediction; 2 % on I is the allowance for a fitted (not drawn) body, 4 to 20 times the
# errors above, and tighter than the 10 % the former parametric body missed by.
SECTION_FIGURES = {  # area mm^2, mass kg/m, I_vertical cm^4, I_lateral cm^4, centroid mm
    "60E1": (7670.0, 60.21, 3038.0, 512.3, 80.9),
    "54E1": (6977.0, 54.77, 2338.0, 419.2, 75.1),
}


def _check_section(p, name):
    area, mass, iv, il, zc = SECTION_FIGURES[name]
    assert p.area == pytest.approx(area * 1e-6, rel=0.005)
    assert p.mass_per_length == pytest.approx(mass, rel=0.005)
    assert p.i_vertical == pytest.approx(iv * 1e-8, rel=0.02)
    assert p.i_lateral == pytest.approx(il * 1e-8, rel=0.02)
    # the centroid (neutral axis) within 0.5 mm of the published height above the foot
    assert p.centroid[1] == pytest.approx(zc * 1e-3, abs=5e-4)
    assert abs(p.centroid[0]) < 1e-9


def test_60e1_area_mass_and_bending(props):
    """Measured (4 mm quad8): 7671.7 mm^2, 60.22 kg/m, 3036.8 / 512.2 cm^4, centroid 80.85 mm."""
    _check_section(props, "60E1")


def test_54e1_area_mass_and_bending(props54):
    """Measured (4 mm quad8): 6980.1 mm^2, 54.79 kg/m, 2337.1 / 418.8 cm^4, centroid 75.06 mm."""
    _check_section(props54, "54E1")


def test_sourced_nominal_dimensions():
    """Height, head width, foot width, web thickness and head depth E as in the British Steel
    table (60E1 172/72/150/16.5, E 51; 54E1 159/70/140/16, E 49.4), to 0.05 mm."""
    for name, (h, bh, bf, tw, e) in {"60E1": (172, 72, 150, 16.5, 51.0),
                                     "54E1": (159, 70, 140, 16.0, 49.4)}.items():
        out = rail_outline(name, size=1e-4) * 1e3
        y, z = out.T
        assert z.max() == pytest.approx(h, abs=0.05) and z.min() == pytest.approx(0.0, abs=1e-9)
        assert np.ptp(y) == pytest.approx(bf, abs=0.05)
        d = PROFILES[name]
        assert d.head_width * 1e3 == pytest.approx(bh, abs=0.05)
        assert 2 * HEADS[name].head_half_width * 1e3 == pytest.approx(bh, abs=0.05)
        assert (d.height - d.head_bottom) * 1e3 == pytest.approx(e, abs=0.05)
        # web thickness: the straight web faces at +-tw/2 between the fillets (width of the
        # outline's crossings with the level halfway up the web)
        level = 0.5 * (d.foot_root + d.head_bottom) * 1e3
        q = np.roll(out, -1, axis=0)
        cross = (np.minimum(out[:, 1], q[:, 1]) <= level) & (np.maximum(out[:, 1], q[:, 1]) > level)
        f = (level - out[cross, 1]) / (q[cross, 1] - out[cross, 1])
        yc = out[cross, 0] + f * (q[cross, 0] - out[cross, 0])
        assert len(yc) == 2 and np.ptp(yc) == pytest.approx(tw, abs=0.05)


def test_54e1_head_tangent_points_derived_by_tangency():
    """The rule that derives the 54E1 shoulder end (corner arc tangent to the 1:20 flank at the
    half head width, crown tangent point as 60E1) reproduces 60E1's published shoulder end
    26.0265 mm from its 36.000 mm; on 54E1 it gives 24.8327 mm at 35.000 mm, as shipped."""
    h60, h54 = HEADS["60E1"], HEADS["54E1"]
    assert shoulder_end_by_tangency(300.0, 10.228, 80.0, 13.0, 36.0, 20.0) == pytest.approx(26.0265, abs=0.05)
    derived = shoulder_end_by_tangency(300.0, 10.228, 80.0, 13.0, 35.0, 20.0)
    assert derived == pytest.approx(h54.shoulder_half_width * 1e3, abs=1e-3)
    for attr in ("crown_radius", "shoulder_radius", "corner_radius", "crown_half_width", "flank_slope"):
        assert getattr(h54, attr) == getattr(h60, attr)
    g = head_arcs(h54, 0.159)
    c, t = g["centres"], g["tangents"]
    np.testing.assert_allclose(t[:, 0] * 1e3, [10.228, 24.8327, 35.0], atol=0.05)
    for i in range(2):  # consecutive arcs tangent (centres and tangent point on one line)
        u = (t[i] - c[i]) / np.linalg.norm(t[i] - c[i])
        v = (t[i] - c[i + 1]) / np.linalg.norm(t[i] - c[i + 1])
        assert math.degrees(math.acos(min(1.0, float(u @ v)))) < 1e-6
    normal = (t[2] - c[2]) / np.linalg.norm(t[2] - c[2])
    flank_normal = np.array([1.0, 1.0 / 20.0]) / math.hypot(1.0, 1.0 / 20.0)
    assert math.degrees(math.acos(min(1.0, float(normal @ flank_normal)))) < 1e-3  # exact by derivation
    # radii of the dense outline between the tangent points, fitted, to 0.05 mm
    out = rail_outline("54E1", size=2e-4)
    field = out[(out[:, 0] >= 0) & (out[:, 1] > 0.159 - 0.02)]
    for y0, y1, r in ((0.0, t[0, 0], 0.300), (t[0, 0], t[1, 0], 0.080)):
        p = field[(field[:, 0] > y0 + 1e-4) & (field[:, 0] < y1 - 1e-4)]
        assert _circle_fit(p)[1] == pytest.approx(r, abs=5e-5)
    corner = field[(field[:, 0] > t[1, 0] + 1e-4) & (field[:, 1] > t[2, 1] + 1e-4)]
    assert _circle_fit(corner)[1] == pytest.approx(0.013, abs=5e-5)


def test_aliases_and_names():
    # UIC60 = 60E1 (EN 13674-1 renamed it); no UIC54 alias: British Steel lists a legacy UIC54
    # with other figures (6934 mm^2, 2346 / 417.5 cm^4) than 54E1 (6977, 2338 / 419.2)
    assert ALIASES == {"UIC60": "60E1"}
    np.testing.assert_array_equal(rail_outline("UIC60"), rail_outline("60E1"))
    RailParams.from_mapping({"profile": "UIC60"}).cross_check()
    RailParams.from_mapping({"profile": "54E1"}).cross_check()
    for refused in ("UIC54", "49E1"):
        with pytest.raises(InputError) as e:
            RailParams.from_mapping({"profile": refused}).cross_check()
        assert e.value.field == "rail.profile"
        for name in (*PROFILES, *ALIASES):
            assert name in e.value.message
    assert polygon_area(rail_outline("BV50")) > 0  # BV50 unchanged (parametric head)


def _pair(n, rail="60E1"):
    fb = flange_back_position(gauge_point(rail, n))
    return WheelRailPair(s1002_profile(), rail_head_profile(rail, n), R0, fb, math.atan(1 / n))


@pytest.mark.parametrize("n", [40, 20])
def test_s1002_on_60e1_centred_contacts_the_crown(n):
    t = contact_table(_pair(n), [0.0])
    assert abs(t.contact_angle[0, 0]) < math.radians(3.0)
    assert abs(t.y_rail[0, 0]) < 0.0125  # within the crown and shoulder of the head (26 mm wide R80 start)
    if n == 40:  # the profile pair S1002 / 60E1 was designed for 1:40: near the tape circle
        assert t.y_wheel[0, 0] == pytest.approx(0.070, abs=0.005)
    else:  # at 1:20 the tread contact moves towards the field side but stays on the tread
        assert 0.070 < t.y_wheel[0, 0] < 0.095


@pytest.mark.parametrize("n", [pytest.param(40, marks=pytest.mark.xfail(
    strict=True, reason="54E1 1:40 centred: contact on the gauge-side shoulder (y_rail -11.0 mm, "
                        "0.069 rad), see docstring")), 20])
def test_s1002_on_54e1_centred_contacts_the_crown(n):
    """54E1 (head arcs assumed as 60E1's, 70 mm wide): the centred S1002 wheelset should touch
    the crown, contact angle below 3 deg, on the tread. At 1:20 it does (0.0092 rad, y_rail
    +10.8 mm, 82.3 mm from the flange back). At 1:40 it does NOT: the head is 2 mm narrower
    than 60E1's, so the gauge point, and with it the centred wheelset, sits 1 mm further to
    the field side of the rail's centre line; on 60E1 the centred 1:40 contact is only 0.3 mm
    of wheelset shift away from its jump to the gauge-side shoulder, so on 54E1 it lies beyond
    that jump (y_rail -11.0 mm, 0.069 rad; the same as 60E1 with the wheelset 1 mm off centre).
    Whether the real 54E1 does the same depends on its head arcs, which are assumed here (no
    reachable source): recorded, not hidden."""
    t = contact_table(_pair(n, "54E1"), [0.0])
    assert abs(t.contact_angle[0, 0]) < math.radians(3.0)
    assert abs(t.y_rail[0, 0]) < 0.0125
    assert 0.060 < t.y_wheel[0, 0] < 0.095


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
