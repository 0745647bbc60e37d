"""Rolling radius difference and equivalent conicity of S1002 on 60E1 at 1:40: project vs brute force.

The project's Delta r(y) is what ``python pipeline.py geometry --set wheel.tread_profile='"S1002"'
--set rail.profile='"60E1"' --set rail.inclination=40 --out DIR`` stores in
``DIR/contact_geometry.h5`` (``wheelset/``): computed here in memory by the same function
(:func:`contact_geometry.study.study_geometry`), or read from such a file with ``--artefact``.
The reference is the brute-force search of :mod:`contact_geometry.reference` on the exact S1002
definition and the exact 60E1 arcs (no published Delta r table for this pair was reachable).
Both conicities use the harmonic linearisation of :mod:`contact_geometry.wheelset`.

Run: ``python benchmarks/conicity_reference.py [--step 1e-6] [--artefact FILE] [--figure PNG]``.
Prints Delta r of both at a few displacements, the largest difference on the tread and at the
flange, the contact jumps of one wheel, the conicities at 3 mm, and writes the figure
(default ``docs/figures/conicity_s1002_60e1.png``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_geometry.artefact import read_wheelset  # noqa: E402
from contact_geometry.contact_search import contact_table  # noqa: E402
from contact_geometry.reference import (ExactRailHead, brute_force_contacts, brute_force_conicity,  # noqa: E402
                                        brute_force_dr)
from contact_geometry.study import pair_from_study, study_geometry  # noqa: E402
from stages.config import load_study  # noqa: E402

SETTINGS = ('wheel.tread_profile="S1002"', 'rail.profile="60E1"', "rail.inclination=40")
FIGURE = Path(__file__).resolve().parent.parent / "docs" / "figures" / "conicity_s1002_60e1.png"
#: Displacements compared (m): the table's -8 ... +8 mm by 0.1 mm.
Y = np.round(np.arange(-80, 81) * 1e-4, 10)
#: |y| from which one wheel touches with its flange root or face (m).
FLANGE_FROM = 5.1e-3
PRINTED_MM = (0.0, 0.2, 0.3, 1.0, 2.0, 3.0, 4.0, 5.0, 5.2, 6.0, 6.6, 6.7, 7.0, 8.0)


def jumps(wheel_position, low=-8e-3, high=8e-3, coarse=1e-4, fine=1e-6, size=1e-3):
    """Displacements (m) where the contact position on the wheel jumps by more than ``size`` (m)
    between displacements ``fine`` apart, with the positions before and after (m)."""
    y = np.linspace(low, high, int(round((high - low) / coarse)) + 1)
    w = wheel_position(y)
    out = []
    for i in np.flatnonzero(np.abs(np.diff(w)) > size):
        m = np.linspace(y[i], y[i + 1], int(round(coarse / fine)) + 1)
        wm = wheel_position(m)
        k = int(np.argmax(np.abs(np.diff(wm))))
        if abs(wm[k + 1] - wm[k]) > size:
            out.append((0.5 * (m[k] + m[k + 1]), wm[k], wm[k + 1]))
    return out


def project_curve(artefact):
    """(displacement, dr, conicity, amplitude, pair) of the project: from ``artefact`` or in memory."""
    study = load_study(assignments=SETTINGS)
    if artefact:
        w = read_wheelset(artefact)
        return (w["displacement"], w["rolling_radius_difference"], w["equivalent_conicity"],
                w["conicity_amplitude"], pair_from_study(study))
    g = study_geometry(study)
    return g.dr_displacement, g.dr, g.equivalent_conicity, g.conicity_amplitude, g.pair


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[2:]))
    parser.add_argument("--step", type=float, default=1e-6, help="lateral grid step of the brute force (m)")
    parser.add_argument("--artefact", help="contact_geometry.h5 written by 'pipeline.py geometry ... --out DIR' "
                                           "(default: compute the project's curve in memory)")
    parser.add_argument("--figure", default=str(FIGURE), help="figure written (PNG)")
    args = parser.parse_args(argv)

    t0 = time.perf_counter()
    y_p, dr_p_all, gamma_p, amp, pair = project_curve(args.artefact)
    t_project = time.perf_counter() - t0
    idx = [int(np.flatnonzero(np.isclose(y_p, v, atol=1e-12))[0]) for v in Y]
    dr_p = np.asarray(dr_p_all)[idx]
    head = ExactRailHead("60E1", 40)
    t0 = time.perf_counter()
    dr_b = brute_force_dr(head, Y, step=args.step)
    gamma_b = brute_force_conicity(head, amp, step=args.step)
    t_brute = time.perf_counter() - t0
    err = np.abs(dr_p - dr_b)
    tread = np.abs(Y) < FLANGE_FROM

    print(f"S1002 on 60E1 1:40, gauge 1435 mm, back-to-back 1360 mm, tape radius {pair.nominal_radius * 1e3:.0f} mm")
    print(f"flange back (rail frame): project {pair.flange_back * 1e3:.4f} mm, exact head {head.flange_back() * 1e3:.4f} mm")
    print(f"brute force: lateral step {args.step * 1e6:g} um, {2 * Y.size} contacts + conicity in {t_brute:.2f} s; "
          f"project {'read' if args.artefact else 'computed'} in {t_project:.2f} s")
    print(f"{'y (mm)':>8} {'dr project (mm)':>16} {'dr brute (mm)':>14} {'diff (um)':>10}")
    for v in PRINTED_MM:
        k = int(np.argmin(np.abs(Y - v * 1e-3)))
        print(f"{Y[k] * 1e3:8.2f} {dr_p[k] * 1e3:16.4f} {dr_b[k] * 1e3:14.4f} {(dr_p[k] - dr_b[k]) * 1e6:10.2f}")
    print(f"max |dr project - dr brute| over -8 ... 8 mm: tread (|y| < {FLANGE_FROM * 1e3:g} mm) "
          f"{err[tread].max() * 1e6:.2f} um, all {err.max() * 1e6:.2f} um at y = {Y[np.argmax(err)] * 1e3:.1f} mm")
    mine = jumps(lambda v: contact_table(pair, v).y_wheel[:, 0])
    ref = jumps(lambda v: brute_force_contacts(head, v, step=args.step).y_wheel)
    print("contact jumps of one wheel (wheel displacement, position on the wheel from the flange back):")
    for name, found in (("project", mine), ("brute force", ref)):
        print(f"  {name:12s}" + "; ".join(f"{j * 1e3:.4f} mm: {a * 1e3:.2f} -> {b * 1e3:.2f} mm" for j, a, b in found))
    print(f"equivalent conicity at {amp * 1e3:g} mm (harmonic linearisation, 256 phases): project {gamma_p:.5f}, "
          f"brute force {gamma_b:.5f}, difference {gamma_p - gamma_b:+.1e}")

    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7.0, 6.2), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    ax.plot(Y * 1e3, dr_p * 1e3, "-", color="C0", lw=1.6,
            label=rf"project (contact-geometry stage), $\gamma_e$(3 mm) = {gamma_p:.4f}")
    ax.plot(Y[::2] * 1e3, dr_b[::2] * 1e3, "o", color="C3", ms=3.2, mfc="none",
            label=rf"brute force on the exact profiles, $\gamma_e$(3 mm) = {gamma_b:.4f}")
    ax.axvspan(-amp * 1e3, amp * 1e3, color="0.92", zorder=0, label="conicity amplitude 3 mm")
    ax.set_ylabel(r"$\Delta r = r(+y) - r(-y)$ (mm)")
    ax.set_title("S1002 on 60E1, inclination 1:40, gauge 1435 mm, back-to-back 1360 mm", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    ax2.plot(Y * 1e3, (dr_p - dr_b) * 1e6, ".-", color="C2", ms=3, lw=0.8)
    ax2.set_ylabel(r"project $-$ brute ($\mu$m)")
    ax2.set_xlabel("lateral wheelset displacement y (mm)")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.figure, dpi=130)
    plt.close(fig)
    print(f"figure: {args.figure}")
    return {"max_diff_tread": float(err[tread].max()), "max_diff": float(err.max()), "conicity_project": gamma_p,
            "conicity_brute": gamma_b}


if __name__ == "__main__":
    main()
