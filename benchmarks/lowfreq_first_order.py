"""The low-frequency (137 / 203 Hz) poles of the default study: first-order prediction against the screen.

Reproduces the contact-angle sweep of docs/results.md (*The default study*: "the formula
reproduces the screen within 5 % over α = 0 … 0.025 rad") and of docs/verification.md: on a
finished default-study folder at μ = 0.6, η = −1.5 %, for the stationary wheel's modes nearest
137.4 and 203.1 Hz it prints the mode's open-loop decay, its shape at the contact (φφᵀ·2iω:
φ_y², φ_z², φ_yφ_z), and for six contact angles from 0 to the computed one the single-mode
growth rate σ ≈ Re p − κ Im K/(2ω) beside the screen's (:func:`stability.screen.screen`),
then the prediction with a rigid rail. tests/test_squeal_mechanism.py checks the same formula
against the exact characteristic polynomial of a one-mode wheel on a one-pole rail, with this
study's n = 0 mode as its numbers.

Nothing is timed. Run (OUT: a default-study output folder, e.g. a copy of a finished
``python pipeline.py run``; the rail fit ``rail_fit.h5`` (stage ``rail-fit``) is built there if missing)::

    python benchmarks/lowfreq_first_order.py OUT
"""
import argparse

import numpy as np

from stages.config import load_study
from stages.screen import structures
from stages.screen import linear_contact, rail_in_contact_frame
from interaction.frame import to_contact_frame
from stability.screen import screen
from stability.rational import evaluate, RationalModel
from fe.greens import receptance


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default="out", help="finished default-study folder")
    args = parser.parse_args(argv)
    study = load_study(None, False, ["contact.friction=0.6", "contact.lateral_creepage=-0.015"])
    models, rail, point = structures(study, args.out, progress=False)
    lin = linear_contact(study, point)
    speed = study["operating"]["speed"]
    mu, kn = lin.sliding_coefficient, lin.normal_stiffness
    d = np.array([0.0, mu, 1.0])
    p, res = models["stationary"]
    p = np.asarray(p); res = np.asarray(res)
    f0 = p.imag / 2 / np.pi
    print("rail fit Hrail zz/yy/yz (upright) at 137, 203 Hz:")
    for f in (137.4, 203.1):
        h = evaluate(rail, [f])[0]
        print(f, "zz", h[2, 2], "yy", h[1, 1], "yz", h[1, 2])

    def predict(k, alpha, rail_alpha, rigid=False):
        R = to_contact_frame(res, alpha)
        s = p[k]
        r = RationalModel.rigid() if rigid else rail_in_contact_frame(rail, rail_alpha)
        f = s.imag / 2 / np.pi
        others = np.ones(p.size, bool); others[k] = False
        h_rest = evaluate(r, [f])[0] + receptance(p[others], R[others], [f])[0] + np.conj(R[k]) / (s - np.conj(s))
        keff = 1.0 / (1.0 / kn + h_rest[2] @ d)
        t = R[k][2] @ d
        shift = -t * keff
        # real-mode view: R = phi phi^T / (2 i w) -> phi
        phi2 = R[k] * 2j * s.imag
        return s + shift, keff, phi2, h_rest

    for target in (137.4, 203.1):
        k = int(np.argmin(abs(f0 - target)))
        print(f"\nmode {k}: {f0[k]:.2f} Hz, open-loop Re p = {p[k].real:.3f} 1/s")
        print("  upright phi phi^T*2iw diag/offdiag (y,z):", np.round((res[k]*2j*p[k].imag)[[1,2,1],[1,2,2]].real, 10))
        for frac in np.linspace(0, 1, 6):
            a = frac * point.contact_angle
            ra = point.rail_section_angle - point.contact_angle + a
            lam, keff, phi2, _ = predict(k, a, ra)
            kap = (phi2[2] @ d).real  # phi_z (phi_z + mu phi_y)
            sc = screen(p, to_contact_frame(res, a), rail_in_contact_frame(rail, ra), lin, speed, 0.1, False)
            near = [q for q in sc["poles"] if abs(q["frequency"] - lam.imag / 2 / np.pi) < 3]
            scr = max((q["growth_rate"] for q in near), default=float("nan"))
            # also least-damped eigenvalue near it, growing or not
            print(f"  alpha {a:.4f}: kappa={kap:+.3e} Im Keff={keff.imag:+.3e} Re Keff={keff.real:.3e} "
                  f"predicted sigma={lam.real:+.3f} 1/s at {lam.imag/2/np.pi:.2f} Hz; screen growing: {scr:+.3f}")
        lam, keff, phi2, _ = predict(k, point.contact_angle, 0, rigid=True)
        print(f"  rigid rail at computed angle: predicted sigma={lam.real:+.4f}, Im Keff={keff.imag:+.3e}")


if __name__ == "__main__":
    main()
