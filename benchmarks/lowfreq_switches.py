"""The low-frequency (137 / 203 Hz) poles of the default study: which ingredient makes them grow.

Reproduces the switches of docs/results.md (*The default study*, why the computed contact
destabilises the n = 0 and n = 1 axial modes) and of docs/verification.md (low-frequency
instability of the inclined contact): on a finished default-study folder, the linear screen
(:func:`stability.screen.screen`) of the stationary and Eulerian wheels at μ = 0.6,
η = −1.5 % (unless overridden) is rerun with one ingredient switched at a time — contact angle
0 (wheel, rail, both), rigid rail, no creep relaxation, μ_s = 0, no longitudinal creep
stiffness, no spin, the normal stiffness × 0.3 and × 3, the upright cross receptance y–z
removed, and the contact angle swept from 0 to twice the computed one. Each line prints the
growing poles between 100 and 300 Hz and the two lowest above (frequency, growth rate 1/s).
Expected (docs/results.md): the poles vanish with the wheel upright, with a rigid rail and with
μ_s = 0, and stay with no spin, no relaxation and the rail's own inclination.
tests/test_squeal_mechanism.py checks the mechanism itself on a one-mode wheel.

Nothing is timed. Run (OUT: a default-study output folder, e.g. a copy of a finished
``python pipeline.py run``; the rail fit ``rail_fit.h5`` (stage ``rail-fit``) is built there if missing)::

    python benchmarks/lowfreq_switches.py OUT [SECTION.KEY=VALUE ...]
"""
import argparse
import dataclasses

import numpy as np

from stages.config import load_study
from stages.screen import structures
from stages.screen import linear_contact, rail_in_contact_frame
from stages.cases import contact_hertz, imposed_creepage
from interaction.frame import to_contact_frame
from contact.params import ContactParams
from contact.point.model import PointContact, linearise_point_contact
from stability.screen import screen
from stability.rational import RationalModel


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default="out", help="finished default-study folder")
    parser.add_argument("set", nargs="*", metavar="SECTION.KEY=VALUE", help="further study overrides")
    args = parser.parse_args(argv)
    OUT = args.out
    sets = ["contact.friction=0.6", "contact.lateral_creepage=-0.015"] + args.set
    study = load_study(None, False, sets)
    models, rail, point = structures(study, OUT, progress=False)
    speed = study["operating"]["speed"]
    lin = linear_contact(study, point)
    print("point: angle", point.contact_angle, "rail angle", point.rail_section_angle, "spin", point.spin,
          "r", point.rolling_radius, "N", point.normal_force)
    print("lin:", lin)

    def run(label, angle=None, rail_angle=None, contact=lin, rigid=False, names=("stationary", "eulerian"), mod=None,
            band=(100, 300)):
        a = point.contact_angle if angle is None else angle
        ra = point.rail_section_angle if rail_angle is None else rail_angle
        r = RationalModel.rigid() if rigid else rail_in_contact_frame(rail, ra)
        out = []
        for n in names:
            p, res = models[n]
            res = np.array(res)
            if mod is not None:
                res = mod(res)
            s = screen(p, to_contact_frame(res, a), r, contact, speed, 0.1, False)
            low = [(round(q["frequency"], 1), round(q["growth_rate"], 2)) for q in s["poles"]
                   if band[0] <= q["frequency"] <= band[1]]
            hi = [(round(q["frequency"]), round(q["growth_rate"], 1)) for q in s["poles"] if q["frequency"] > band[1]][:2]
            out.append(f"{n}: low {low} high {hi}")
        print(f"{label:45s} | " + " | ".join(out), flush=True)

    run("baseline")
    run("angle 0 (wheel+rail)", angle=0.0, rail_angle=0.0)
    run("wheel angle 0 only", angle=0.0)
    run("rail angle 0 only", rail_angle=0.0)
    run("rigid rail", rigid=True)
    run("rigid rail, angle 0", angle=0.0, rigid=True)
    run("no relaxation", contact=dataclasses.replace(lin, relaxation=None))
    run("mu_s = 0", contact=dataclasses.replace(lin, sliding_coefficient=0.0))
    run("c_x = 0", contact=dataclasses.replace(lin, creep_stiffness=(0.0, lin.creep_stiffness[1])))
    xi, eta, phi = imposed_creepage(study, point)
    contact = ContactParams.from_mapping(study["contact"], "contact")
    material, hertz = contact_hertz(study, point)
    model = PointContact(material=material, friction=contact.to_friction(), hertz=hertz, kind="transient",
                         speed=speed, time_step=study["time"]["time_step"])
    lin0 = linearise_point_contact(model, point.normal_force, (xi, eta, 0.0))
    print("lin no spin:", lin0)
    run("spin 0", contact=lin0)
    run("spin 0, angle 0", contact=lin0, angle=0.0, rail_angle=0.0)
    for f in (0.3, 3.0):
        run(f"k_n x{f}", contact=dataclasses.replace(lin, normal_stiffness=lin.normal_stiffness * f))
    def no_cross(res):
        res = res.copy(); res[:, 1, 2] = 0; res[:, 2, 1] = 0; return res
    run("upright yz cross receptance 0", mod=no_cross)
    run("upright yz cross 0, angle 0", mod=no_cross, angle=0.0, rail_angle=0.0)
    for a in np.linspace(0, 1, 6) * point.contact_angle:
        run(f"angle {a:.4f} (wheel & rail shifted)", angle=a, rail_angle=point.rail_section_angle - point.contact_angle + a)
    for a in (-0.025, 0.05, 0.1):
        run(f"angle {a:.4f}", angle=a, rail_angle=point.rail_section_angle - point.contact_angle + a)


if __name__ == "__main__":
    main()
