"""Steady curving checks (issue 35 item 1): the table of docs/results.md, "Steady curving checks".

Two parts, printed as one Markdown table (radius, case, quantity, ours, reference, difference):

* **linear theory** — ``curving.solve_bogie`` on a cone (λ = 0.1, r0 = 0.45 m, l0 = 0.75 m, 20 mm
  clearance, μ = 1, spin off) against the linear theory of curving by creep forces
  (``curving.linear_theory``, Boocock 1969, solved by numpy.linalg.solve): the rigid bogie and
  the bogie with primary yaw stiffness, balanced cant (5 m/s) and a cant deficiency (30 m/s on
  level track), at R = 2000 and 5000 m, and the Richardson extrapolation to no saturation;
  the tolerance of tests/test_curving_linear.py is β/3 + 1e-4 (β the linear force over μN);
* **standard profiles** — the default rigid bogie on S1002 / 60E1 1:40 at 150 m (10 m/s, μ = 0.3)
  and 300 m (15 m/s, μ = 0.4) against the expectations of tests/test_curving_profiles.py.

Run: ``python benchmarks/curving_checks.py`` (about 5 s).
"""

from __future__ import annotations

import math
import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import numpy as np  # noqa: E402

from curving import ConicalGeometry, CurvingParams, profile_geometry, solve_bogie  # noqa: E402
from curving.linear_theory import linear_bogie  # noqa: E402
from stages.config import load_study  # noqa: E402

CONE = ConicalGeometry(wheel_radius=0.45, contact_half_spacing=0.75, conicity=0.1, flangeway_clearance=0.02)
B = 1.25
CASES = {"rigid": {}, "primary yaw k_x = 1e7, k_y = 5e6 N/m": dict(longitudinal_stiffness=1e7, lateral_stiffness=5e6),
         "primary yaw k_x = 2e6, k_y = 2e6 N/m": dict(longitudinal_stiffness=2e6, lateral_stiffness=2e6)}


def _cone_case(radius, stiff, deficiency):
    speed = 30.0 if deficiency else 5.0
    cant = 0.0 if deficiency else 2 * 0.75 * math.sin(math.atan(speed ** 2 / (9.81 * radius)))
    p = CurvingParams(radius=radius, speed=speed, cant=cant, friction=1.0, spin=False, geometry=CONE, **stiff)
    r = solve_bogie(p)
    lin = linear_bogie(CONE, radius, speed, cant=cant, **stiff)
    ys = np.array([w["lateral_displacement"] for w in r["wheelsets"]])
    psis = np.array([w["angle_of_attack"] for w in r["wheelsets"]])
    return ys, psis, lin


def linear_rows(radii=(2000.0, 5000.0)):
    """One row per case and radius (the leading wheelset's ψ, the largest departures over both
    wheelsets) and one per case for the departure extrapolated to no saturation (Richardson on
    the two radii: the departure is c1 β + c2 β², β ∝ 1/R)."""
    rows = []
    q = radii[1] / radii[0]
    for name, stiff in CASES.items():
        for deficiency in (False, True):
            label = f"{name}, {'cant deficiency (30 m/s, level track)' if deficiency else 'balanced cant'}"
            departures = []
            for radius in radii:
                ys, psis, lin = _cone_case(radius, stiff, deficiency)
                d = np.r_[ys / np.array(lin.lateral_displacement) - 1,
                          (psis - np.array(lin.angle_of_attack)) / (B / radius)]
                departures.append(d)
                rows.append((radius, label, "ψ leading (mrad)", psis[0] * 1e3, lin.angle_of_attack[0] * 1e3,
                             f"largest: Δy {np.max(np.abs(d[:2])) * 100:.2f} % of y, Δψ "
                             f"{np.max(np.abs(d[2:])) * 100:.2f} % of b/R (tol. β/3 = "
                             f"{lin.force_ratio / 3 * 100:.1f} %)"))
            extrapolated = (q * departures[1] - departures[0]) / (q - 1.0)
            rows.append((f"{radii[0]:g}, {radii[1]:g} → ∞", label, "largest departure extrapolated to β → 0",
                         None, None, f"{np.max(np.abs(extrapolated)) * 100:.3f} %"))
    return rows


def profile_rows():
    geometry = profile_geometry(load_study(assignments=('wheel.tread_profile="S1002"', 'rail.profile="60E1"',
                                                       "rail.inclination=40")))
    rows = [("—", "S1002 / 60E1 1:40 geometry", "flange contact angle (°)",
             math.degrees(geometry.flange().contact_angle), 70.0, "S1002 flank (EN 13715)")]
    for radius, speed, mu in ((150.0, 10.0, 0.3), (300.0, 15.0, 0.4)):
        r = solve_bogie(CurvingParams(radius=radius, speed=speed, friction=mu, geometry=geometry))
        lead, trail = r["wheelsets"]
        wheels = {(w["wheelset"], w["side"]): w for w in r["wheels"]}
        outer, inner = wheels["leading", "outer"], wheels["leading", "inner"]
        flange = next(c for c in outer["contacts"] if c["kind"] == "flange")
        tan_f = math.tan(flange["contact_angle"])
        nadal = (tan_f - mu) / (1 + mu * tan_f)
        label = f"S1002 / 60E1 1:40, rigid, {speed:g} m/s, μ = {mu:g}"
        two_b = 2 * B / radius
        psi1, psi2 = lead["angle_of_attack"], trail["angle_of_attack"]
        rows += [
            (radius, label, "ψ leading (mrad)", psi1 * 1e3, two_b * 1e3, f"{psi1 / two_b:.3f} × 2b/R (expected 0.75–1.25)"),
            (radius, label, "ψ trailing (mrad)", psi2 * 1e3, 0.0, f"{psi2 / two_b:+.3f} × 2b/R (expected within ±0.25)"),
            (radius, label, "η leading inner (wheel frame, %)", inner["creepage"][1] * 100,
             psi1 * math.cos(inner["contact_angle"]) * 100, "+ψ cos δ (−ψ towards the outer rail)"),
            (radius, label, "Y/Q leading outer", outer["derailment_quotient"], nadal,
             f"Nadal limit of the {math.degrees(flange['contact_angle']):.0f}° flank"),
            (radius, label, "flange force (kN)", outer["flange_force"] / 1e3, None, "> 0"),
            (radius, label, "largest residual (N)", max(r["residuals"]["lateral_force"], r["residuals"]["yaw_moment"]
                                                         / 0.75, r["residuals"]["axle_torque"] / 0.75), None,
             f"tolerance {r['tolerance']['force']:.0e} N"),
        ]
    return rows


def _fmt(v):
    if v is None:
        return "—"
    if isinstance(v, str):
        return v
    return f"{v:.4g}"


def main():
    print("| radius (m) | case | quantity | ours | reference | difference |")
    print("|---|---|---|---|---|---|")
    for row in linear_rows() + profile_rows():
        radius = row[0] if isinstance(row[0], str) else f"{row[0]:g}"
        print(f"| {radius} | {row[1]} | {row[2]} | {_fmt(row[3])} | {_fmt(row[4])} | {row[5]} |")


if __name__ == "__main__":
    main()
