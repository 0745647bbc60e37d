"""Tests of the contact-geometry package against closed forms and a brute-force search."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from contact_geometry import ContactPoint
from contact_geometry.contact_search import (STEEL_CONTACT_MODULUS, WheelRailPair, contact_exists, contact_interval,
                                             contact_table)
from contact_geometry.plots import plot_contact_geometry
from contact_geometry.study import pair_from_study
from contact_geometry.track import flange_back_position
from contact_geometry.wheel_surface import parametric_wheel_profile
from contact_geometry.wheelset import equivalent_conicity, rolling_radius_difference
from profiles.curve import Profile, read_profile
from profiles.rail_head import gauge_point, inclined_outline, rail_head_profile
from profiles.s1002 import S1002_JOINTS_MM, S1002_TAPE_OFFSET, s1002_height, sample_s1002
from profiles.wheel_treads import cone_profile, s1002_profile
from squealcore.errors import InputError
from stages.config import load_study

R0 = 0.39  # tape circle radius (m)


def circle_rail(radius=0.3, half_width=0.035, top=0.155, step=1e-4, name="circular crown"):
    """Rail head of circular crown, top at y = 0."""
    y = np.arange(-half_width, half_width + 0.5 * step, step)
    return Profile(y, top - radius + np.sqrt(radius**2 - y**2), name)


# --- S1002 definition -------------------------------------------------------------------------

def test_s1002_continuity_at_joints():
    # Height to 2e-4 mm (rounding of the published coefficients; largest jump 1.2e-4 mm at
    # s = -35 mm), slope to 2e-4 (one-sided differences over 1e-4 mm carry |F''| h < 1e-4).
    h = 1e-4
    for s in S1002_JOINTS_MM[1:-1]:
        left, right = s1002_height(s - 1e-9), s1002_height(s)
        assert abs(left - right) < 2e-4, s
        slope_l = (s1002_height(s - 1e-9) - s1002_height(s - h)) / h
        slope_r = (s1002_height(s + h) - s1002_height(s)) / h
        assert abs(slope_l - slope_r) < 2e-4 * max(1.0, abs(slope_l)), s


def test_s1002_landmarks_and_data_file():
    # Flange tip 28 mm above the tape circle at s = -55 mm, tape circle at 0, 1:15 chamfer.
    assert s1002_height(-55.0) == pytest.approx(28.0, abs=1e-9)
    assert s1002_height(0.0) == pytest.approx(0.0, abs=1e-12)
    assert s1002_height(60.0) - s1002_height(40.0) == pytest.approx(-20.0 / 15.0, rel=1e-6)
    shipped = s1002_profile()
    fresh = sample_s1002()
    np.testing.assert_allclose(shipped.y, fresh.y, atol=1e-12)
    np.testing.assert_allclose(shipped.z, fresh.z, atol=1e-12)
    # flange thickness 32.5 mm, measured 10 mm above the tape circle (EN 13715)
    y = np.linspace(0.001, 0.06, 200001)
    above = shipped.height(y) >= 0.010
    width = y[above].max() - y[above].min() + (y[above].min())  # from the flange back
    assert width == pytest.approx(0.0325, abs=2e-5)


# --- rail head ----------------------------------------------------------------------------------

def test_rail_inclination_and_gauge_point():
    upright = rail_head_profile("BV50", 0)
    assert upright.height(0.0, 1) == pytest.approx(0.0, abs=1e-9)
    assert gauge_point("BV50", 0) == pytest.approx(-0.035, abs=1e-9)
    for n in (20, 30, 40):
        tilted = rail_head_profile("BV50", n)
        assert tilted.height(0.0, 1) == pytest.approx(1.0 / n, rel=1e-6)
    assert gauge_point("BV50", 30) > -0.035  # the gauge side turns down and inwards
    assert flange_back_position(-0.035) == pytest.approx(-0.0725, abs=1e-12)
    with pytest.raises(InputError, match=r"rail\.inclination"):
        rail_head_profile("BV50", 25)


# --- closed forms -------------------------------------------------------------------------------

@pytest.mark.parametrize("wheel", ["cone", "parametric"])
def test_cone_on_circular_crown(wheel):
    gamma, R = 0.025, 0.3
    # the parametric wheel has a flange: a narrower crown keeps it off the flange root
    prof = cone_profile(gamma) if wheel == "cone" else parametric_wheel_profile()
    rail = circle_rail(R) if wheel == "cone" else circle_rail(R, half_width=0.02)
    pair = WheelRailPair(prof, rail, R0, -0.070)
    d = np.linspace(-0.004, 0.004, 17)
    t = contact_table(pair, d)
    y_contact = -R * gamma / math.sqrt(1.0 + gamma**2)  # crown slope equals the cone's
    np.testing.assert_allclose(t.y_rail[:, 0], y_contact, rtol=1e-6)
    np.testing.assert_allclose(t.contact_angle[:, 0], math.atan(gamma), rtol=1e-6)
    yw = y_contact - (-0.070 + d)
    r_exact = R0 - gamma * (yw - 0.070)  # = R0 + gamma d + const: slope dr/dy_w = gamma
    np.testing.assert_allclose(t.rolling_radius[:, 0], r_exact, rtol=1e-6)
    np.testing.assert_allclose(np.diff(t.rolling_radius[:, 0]) / np.diff(d), gamma, rtol=1e-6)
    np.testing.assert_allclose(t.curvature_lat[:, 0], 1.0 / R, rtol=1e-6)
    delta = math.atan(gamma)
    np.testing.assert_allclose(t.spin[:, 0], math.sin(delta) / r_exact, rtol=1e-6)
    assert np.all(t.n_contacts == 1)


def test_two_circles_curvatures_and_hertz():
    r0, Rw, Rr, load = 0.4, 0.8, 0.8, 60e3
    y = np.arange(0.0, 0.14, 1e-4)
    wheel = Profile(y, np.sqrt(Rw**2 - (y - 0.07) ** 2) - Rw, "circular wheel")
    pair = WheelRailPair(wheel, circle_rail(Rr), r0, -0.070)
    d = np.array([0.0, 0.004, -0.006, 0.01])
    t = contact_table(pair, d, wheel_load=load)
    # contact on the line of centres: y_r = Rr d / (Rr + Rw), sin(delta) = -d / (Rr + Rw)
    delta = -np.arcsin(d / (Rr + Rw))
    np.testing.assert_allclose(t.y_rail[:, 0], Rr * d / (Rr + Rw), rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(t.contact_angle[:, 0], delta, rtol=1e-6, atol=1e-12)
    yw = t.y_rail[:, 0] + 0.070 - d
    r = r0 + np.sqrt(Rw**2 - (yw - 0.07) ** 2) - Rw
    np.testing.assert_allclose(t.rolling_radius[:, 0], r, rtol=1e-9)
    np.testing.assert_allclose(t.curvature_lat[:, 0], 1 / Rw + 1 / Rr, rtol=1e-6)
    np.testing.assert_allclose(t.curvature_long[:, 0], np.cos(delta) / r, rtol=1e-9)
    np.testing.assert_allclose(t.normal_force[:, 0], load / np.cos(delta), rtol=1e-12)
    # d = 0: A = 1/(2 r0) = B = (1/Rw + 1/Rr)/2, a circular Hertz contact of radius
    # a = (3 N R / (4 E*))^(1/3) with 1/R = A + B (Johnson 1985, eq. 4.22)
    a_exact = (3.0 * load * (1.0 / 2.5) / (4.0 * STEEL_CONTACT_MODULUS)) ** (1.0 / 3.0)
    assert t.semi_axis_a[0, 0] == pytest.approx(a_exact, rel=1e-5)
    assert t.semi_axis_b[0, 0] == pytest.approx(a_exact, rel=1e-5)


# --- brute force --------------------------------------------------------------------------------

def _brute_force(d_values, fb):
    """Max over dense rail outline points of z_r + z_w, z_w interpolated on a dense S1002 cloud."""
    ws = np.arange(0.0005, 0.130, 1e-5)
    wz = s1002_height((ws - S1002_TAPE_OFFSET) * 1e3) * 1e-3
    pts = inclined_outline("BV50", 30, step=1e-4)
    pts = pts[pts[:, 1] > pts[:, 1].max() - 0.03]
    out_y, out_f = [], []
    for d in d_values:
        yw = pts[:, 0] - (fb + d)
        ok = (yw > ws[0]) & (yw < ws[-1])
        f = np.where(ok, pts[:, 1] + np.interp(yw, ws, wz), -np.inf)
        k = int(np.argmax(f))
        out_y.append(pts[k, 0])
        out_f.append(f[k])
    return np.array(out_y), np.array(out_f)


def test_solver_matches_brute_force_including_flange_jump():
    fb = flange_back_position(gauge_point("BV50", 30))
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), R0, fb)
    d = np.arange(-0.006, 0.0095, 2.5e-4)
    t = contact_table(pair, d)
    y_bf, f_bf = _brute_force(d, fb)
    yr = t.y_rail[:, 0]
    f_solver = pair.rail.height(yr) + pair.wheel.height(yr - fb - d)
    # The wheel's vertical position agrees within the errors of the two representations:
    # the brute-force rail cloud's 0.1 mm chords lie h^2 / (8 R cos(delta)) below the arcs
    # (R >= 13 mm at the head corner, delta the contact angle); the published S1002 pieces
    # themselves jump by 1.2e-7 m at s = -35 mm, which the spline smooths over.
    tol = (1e-4) ** 2 / (8 * 0.013 * np.cos(t.contact_angle[:, 0])) + 1.2e-7 + 1e-9
    assert np.all(np.abs(f_solver - f_bf) <= tol)
    # contact positions agree to 0.15 mm (the cloud's 0.1 mm spacing) except next to a jump
    jumps_s = np.flatnonzero(np.abs(np.diff(yr)) > 0.003)
    jumps_b = np.flatnonzero(np.abs(np.diff(y_bf)) > 0.003)
    assert len(jumps_s) >= 1, "the range must include a jump of the contact point"
    assert len(jumps_s) == len(jumps_b)
    assert np.all(np.abs(jumps_s - jumps_b) <= 1)
    near_jump = np.zeros(d.size, bool)
    for j in jumps_s:
        near_jump[max(0, j - 1):j + 3] = True
    assert np.all(np.abs(yr - y_bf)[~near_jump] < 1.5e-4)
    # flange contact at the largest displacement: contact angle near the 70 deg flange face
    assert math.degrees(t.contact_angle[-1, 0]) > 60.0


def test_two_point_contact_detected():
    # S1002 on BV50 1:30: the contact jumps from the crown to the gauge corner near
    # y_w = -1 mm; where the two gaps are equal, both points touch.
    fb = flange_back_position(gauge_point("BV50", 30))
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), R0, fb)
    d = np.linspace(-0.003, 0.0, 301)
    t = contact_table(pair, d, two_point_tol=0.0)
    jump = int(np.flatnonzero(np.abs(np.diff(t.y_rail[:, 0])) > 0.003)[0])
    # bracket the jump and bisect to where both maxima are equal within 1e-8 m
    lo, hi = d[jump], d[jump + 1]
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        y_mid = contact_table(pair, [mid], two_point_tol=0.0).y_rail[0, 0]
        if abs(y_mid - t.y_rail[jump, 0]) < 0.003:
            lo = mid
        else:
            hi = mid
    both = contact_table(pair, [lo], two_point_tol=1e-6)
    assert both.n_contacts[0] == 2
    assert abs(both.y_rail[0, 0] - both.y_rail[0, 1]) > 0.003
    assert 0.0 <= both.separation[0, 1] <= 1e-6
    # away from the jump (0.5 mm before it) a single contact remains
    single = contact_table(pair, [d[jump] - 5e-4], two_point_tol=1e-6)
    assert single.n_contacts[0] == 1


# --- wheelset -----------------------------------------------------------------------------------

def test_rolling_radius_difference_grows_towards_the_flange():
    # (antisymmetry of dr(y) for a symmetric wheelset holds by construction, r(+y) - r(-y), so it
    # is not tested; what can fail is the growth of the rolling radius towards the flange)
    fb = flange_back_position(gauge_point("BV50", 30))
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), R0, fb)
    dr = rolling_radius_difference(pair, np.linspace(0.0005, 0.006, 24))
    assert np.all(dr > 0.0)
    assert np.all(np.diff(dr) >= -1e-12)


def test_equivalent_conicity_of_cone():
    for gamma in (0.025, 0.05):
        pair = WheelRailPair(cone_profile(gamma), circle_rail(0.3), R0, -0.070)
        dr = rolling_radius_difference(pair, [0.002])
        assert dr[0] == pytest.approx(2 * gamma * 0.002, rel=1e-6)
        for amp in (0.001, 0.003):
            assert equivalent_conicity(pair, amp) == pytest.approx(gamma, rel=1e-6)


# --- bad input ----------------------------------------------------------------------------------

def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_profile_file_units_and_comments(tmp_path):
    p = _write(tmp_path, "mm.txt", "# MiniProf export\n# units: mm\n0, 1\n1 2\n2 2.5  # c\n3 2.6\n")
    prof = read_profile(p)
    np.testing.assert_allclose(prof.y, [0, 1e-3, 2e-3, 3e-3])
    np.testing.assert_allclose(prof.z, [1e-3, 2e-3, 2.5e-3, 2.6e-3])


@pytest.mark.parametrize("text, problem", [
    ("0 0\n1 1\n2 0\n", "too few points"),
    ("0 0\n1 1\n2 nan\n3 0\n", "non-finite"),
    ("0 0\n0.01 0.001\n0.005 0.002\n0.02 0.0\n", "non-monotonic"),
    ("0 0\n0.02 0.01\n0.01 -0.01\n0.01 0.02\n0.03 0.0\n", "self-intersecting"),
    ("0 0\n1 1 1\n2 0\n3 0\n", "2 columns"),
    ("# units: inch\n0 0\n1 1\n2 0\n3 0\n", "units"),
])
def test_bad_profile_files(tmp_path, text, problem):
    p = _write(tmp_path, "bad_profile.txt", text)
    with pytest.raises(InputError, match=problem) as err:
        read_profile(p)
    assert str(p) in str(err.value)


def test_missing_profile_file(tmp_path):
    p = tmp_path / "absent.txt"
    with pytest.raises(InputError, match="cannot read") as err:
        read_profile(p)
    assert str(p) in str(err.value)


def test_no_contact_names_the_file(tmp_path):
    # a rail file covering only y in [10, 30] mm: the cone would touch at y = -7.5 mm
    y = np.arange(0.010, 0.030, 1e-4)
    lines = "\n".join(f"{a:.6e} {b:.9e}" for a, b in zip(y, np.sqrt(0.09 - y**2)))
    p = _write(tmp_path, "narrow_rail.txt", lines + "\n")
    pair = WheelRailPair(cone_profile(0.025), read_profile(p), R0, -0.070)
    with pytest.raises(InputError, match="no contact") as err:
        contact_table(pair, [0.0, 0.001])
    assert str(p) in str(err.value)


# --- figure -------------------------------------------------------------------------------------

def test_plot_contact_geometry(tmp_path):
    fb = flange_back_position(gauge_point("BV50", 30))
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), R0, fb)
    t = contact_table(pair, np.linspace(-0.006, 0.008, 57))
    fig = plot_contact_geometry(pair, t, show=(0.0, 0.007), path=tmp_path / "geometry.png")
    assert (tmp_path / "geometry.png").stat().st_size > 0
    # the rolling-radius curve shows the table (mm)
    line = fig.axes[1].lines[0]
    np.testing.assert_allclose(line.get_ydata(), t.rolling_radius[:, 0] * 1e3)
    # the drawn wheel touches the rail at the contact point of slot 0 (y_w = 0 row)
    k = int(np.argmin(np.abs(t.displacement)))
    wheel_line = fig.axes[0].lines[1]
    yr = t.y_rail[k, 0] * 1e3
    z_wheel = np.interp(yr, wheel_line.get_xdata(), wheel_line.get_ydata())
    assert z_wheel == pytest.approx(pair.rail.height(t.y_rail[k, 0]) * 1e3, abs=1e-3)


# --- symmetric wheelset -------------------------------------------------------------------------

def _wheelset_brute_force(y_values, fb, gauge_offset=0.0):
    """Rolling radii of the right and left wheel of a wheelset shifted by y, in one global frame.

    Global lateral x (m) positive to the right; the right rail's centre line at x = +c, the left
    one's at x = -c (mirror image), each rail inclined towards the track centre; the wheels are
    rigidly joined with their flange backs at x = +-b (c - b = -fb, the centred flange back of
    the one-wheel model). Each wheel is lowered onto its rail separately: the contact is the
    maximum over a dense global grid of rail height + wheel height (both point clouds,
    interpolated linearly), which is not symmetric about x = 0 (it starts at an odd offset).
    """
    ws = np.arange(0.0005, 0.130, 1e-5)
    wz = s1002_height((ws - S1002_TAPE_OFFSET) * 1e3) * 1e-3
    head = rail_head_profile("BV50", 30)
    ry = np.arange(head.y[0], head.y[-1], 1e-5)
    rz = head.height(ry)  # the rail head as the solver sees it, sampled (the wheel is the S1002 formula)
    c = 0.7175
    b = c + fb
    x = np.arange(-0.80, 0.80, 1e-5) + 3.3e-6
    radii = []
    for y in y_values:
        r = []
        for side in (1.0, -1.0):
            rail_y = side * x - c            # track-frame y of each rail (field side positive)
            wheel_s = side * (x - y) - b     # distance from the wheel's flange back
            ok = (rail_y > ry[0]) & (rail_y < ry[-1]) & (wheel_s > ws[0]) & (wheel_s < ws[-1])
            f = np.where(ok, np.interp(rail_y, ry, rz) + np.interp(wheel_s, ws, wz), -np.inf)
            k = int(np.argmax(f))
            r.append(R0 + np.interp(wheel_s[k], ws, wz))
        radii.append(r)
    return np.array(radii)


def test_rolling_radius_difference_of_a_symmetric_wheelset():
    # dr of the solver, r(+y) - r(-y) from the one-wheel model, against a global-frame model of
    # both wheels on both rails; and the global model's dr is antisymmetric: dr(-y) = -dr(y).
    fb = flange_back_position(gauge_point("BV50", 30))
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), R0, fb)
    y = np.linspace(0.0, 0.006, 25)
    radii = _wheelset_brute_force(np.concatenate([y, -y]), fb)
    dr_global = radii[:, 0] - radii[:, 1]
    dr_plus, dr_minus = dr_global[:y.size], dr_global[y.size:]
    dr = rolling_radius_difference(pair, y)
    # near a jump of the contact point (crown -> gauge corner of one wheel) both may pick either
    # maximum: rows whose contact moves by > 3 mm from the neighbours are left out
    table = contact_table(pair, np.concatenate([y, -y]))
    jumps = np.abs(np.diff(table.y_rail[:, 0])) > 0.003
    near = np.zeros(2 * y.size, bool)
    near[:-1] |= jumps
    near[1:] |= jumps
    keep = ~(near[:y.size] | near[y.size:])
    assert keep.sum() >= 15
    # The brute-force contact lies within h = 1e-5 m of the true one: half its grid step, plus
    # the shift of the maximum by the wheel cloud's linear interpolation, sqrt(2 eps / kappa)
    # with eps = k_w h^2 / 8 and the relative curvature kappa >= k_w (convex rail), i.e. < h / 2.
    # So each radius is off by < 1e-5 |tan delta|, the wheel's slope at the contact (observed:
    # below 0.45 of this bound).
    slope = np.abs(np.tan(table.contact_angle[:, 0]))
    tol = 1e-5 * (slope[:y.size] + slope[y.size:])
    assert np.all(np.abs(dr_plus - dr)[keep] <= tol[keep])
    assert np.all(np.abs(dr_minus + dr_plus)[keep] <= 2 * tol[keep])
    assert abs(dr_global[0]) <= 2 * tol[0]


# --- contact points in the rail section's frame ---------------------------------------------------

def test_contact_point_in_the_rail_section_frame():
    # the inclined rail's contact point, turned back, lies on the upright head profile, with the
    # upright profile's slope equal to tan(rail_section_angle)
    pair = pair_from_study(load_study())
    assert pair.rail_tilt == pytest.approx(math.atan(1 / 30), rel=1e-12)
    upright = rail_head_profile("BV50", 0)
    d = np.linspace(-0.008, 0.0099, 13)
    table = contact_table(pair, d)
    for i in range(d.size):
        c = ContactPoint.from_table(table, i, 0, pair)
        assert c.lateral_displacement == d[i]
        assert c.rail_lateral == table.y_rail[i, 0] and c.rolling_radius == table.rolling_radius[i, 0]
        assert c.rail_section_height == pytest.approx(float(upright.height(c.rail_section_lateral)), abs=2e-6)
        assert math.tan(c.rail_section_angle) == pytest.approx(float(upright.height(c.rail_section_lateral, 1)),
                                                               rel=2e-3, abs=2e-4)
        assert c.rail_section_angle == pytest.approx(c.contact_angle - math.atan(1 / 30), rel=1e-12)
    with pytest.raises(IndexError, match="no slot 1"):
        ContactPoint.from_table(table, 0, 1, pair)


def test_contact_point_to_dict_is_json():
    pair = WheelRailPair(cone_profile(0.025), circle_rail(0.3), R0, -0.070)
    c = ContactPoint.from_table(contact_table(pair, [0.001]), 0, 0, pair)
    d = json.loads(json.dumps(c.to_dict(), allow_nan=False))
    assert d["semi_axes"] == [c.semi_axis_a, c.semi_axis_b]
    assert d["contact_angle"] == c.contact_angle and d["n_contacts"] == 1
    # upright rail (no tilt): the section frame is the track frame
    assert d["rail_section_lateral"] == pytest.approx(c.rail_lateral, abs=1e-15)
    flat = ContactPoint(**{**{k: v for k, v in d.items() if k != "semi_axes"}, "semi_axis_a": float("nan")})
    assert flat.to_dict()["semi_axis_a"] is None


# --- where the profiles meet --------------------------------------------------------------------

def test_contact_interval_matches_the_solver():
    # a narrow wheel (80 mm): at large field-side displacements the rail crown contact leaves it
    pair = WheelRailPair(cone_profile(0.025, width=0.08), circle_rail(0.3), R0, -0.070)
    lo, hi = contact_interval(pair, -0.02, 0.02, 1e-4)
    assert hi == pytest.approx(0.02)
    # the cone touches the crown at y = -7.5 mm, i.e. 62.5 mm - d from the flange back: it must lie
    # on the 80 mm wide wheel, d > -17.5 mm. The solver refuses a maximum on the last grid point
    # of the wheel, so the end is conservative by up to the displacement step plus two search-grid
    # steps (the maximum and the rounding of the grid ends), 0.1 mm each.
    assert -0.0175 <= lo <= -0.0175 + 3e-4 + 1e-12
    contact_table(pair, [lo, hi])
    for outside in (lo - 2e-4, lo - 1e-3):
        assert not contact_exists(pair, [outside])[0]
        with pytest.raises(InputError, match="no contact"):
            contact_table(pair, [outside])
