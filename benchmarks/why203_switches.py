"""Switch the ingredients of the 137/203 Hz poles on and off in the linear screen (in-process).

Usage: PYTHONPATH=$PWD python benchmarks/why203_switches.py OUT [SECTION.KEY=VALUE ...]   (OUT: a default-study
output folder; mu = 0.6, eta = -1.5 % unless overridden).
"""
import dataclasses
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # noqa: the package first
from stages.config import load_study
from stages.stability_cli import structures
from stages.screen import ContactParams, PointContact, contact_hertz, linear_contact, rail_in_contact_frame
from stages.cases import imposed_creepage
from interaction.frame import to_contact_frame
from interaction.stability import screen, linearise_point_contact
from interaction.rational import RationalModel

OUT = sys.argv[1] if len(sys.argv) > 1 else "out"
sets = ["contact.friction=0.6", "contact.lateral_creepage=-0.015"] + sys.argv[2:]
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
