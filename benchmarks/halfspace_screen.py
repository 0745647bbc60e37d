"""The screen with the linearised half-space contact on the map's half-space confirmation points.

Usage: python benchmarks/halfspace_screen.py MAP_DIR [INDEX:WHEEL_MODEL ...]

MAP_DIR: the output folder of ``pipeline.py map --config studies/maps.toml`` (its ``maps/wheels``
and ``maps/rails`` are read, nothing is written). Default points: the four of the half-space
confirmation in docs/results.md (870:moving_load disagreed). Per point it prints both
linearisations (point law, steady half-space), the screen's margin with each, the pole near the
time domain's 212 Hz tone, and the screen with one ingredient of the half-space linearisation
switched to the point law's (as benchmarks/lowfreq_switches.py does for the 203 Hz pole), then the
finite-difference step study of the half-space slopes and the time per linearisation. Where
FREQUENCIES names one, the lateral creep force's small-signal response of the transient
half-space (``transient_creep_response``) is compared with the screen's relaxed law.
"""
import argparse
import dataclasses
import logging
import time

import numpy as np

from contact.halfspace.linearise import (
    linearise_halfspace_contact,
    steady_jacobian,
    transient_creep_response,
)
from squealcore.study import get_section
from stability.screen import closed_loop_eigenvalues
from stages.cases import case_study, contact_model, imposed_creepage
from stages.config import load_study
from stages.maps import ContactCache, plan
from stages.screen import (
    WheelModels,
    linear_contact,
    rail_in_contact_frame,
    read_rail_fit,
    wheel_at_contact,
    wheel_point,
)
from stages.wheel import read_mesh, read_modes

DEFAULT_POINTS = ("342:stationary", "978:stationary", "870:moving_load", "652:stationary")
#: The time domain's growing tone at the disagreeing point (Hz) and the band searched around it.
TONE, TONE_BAND = 212.1, 3.0


def pole_near(lam, frequency, band=TONE_BAND):
    """The least stable eigenvalue within ``band`` Hz of ``frequency`` (None if there is none)."""
    hz = lam.imag / (2 * np.pi)
    sel = np.flatnonzero((np.abs(hz - frequency) <= band) & (lam.imag > 0))
    return None if sel.size == 0 else lam[sel[np.argmax(lam.real[sel])]]


#: Frequencies (Hz) of the transient check per configuration: the poles the two relaxations move
#: (891 Hz grows with the no-slip relaxation at 978, 212 Hz is the time domain's tone at 870).
FREQUENCIES = {978: (891.19,), 870: (212.12,)}


def creep_response(lin, frequency, speed):
    """The screen's lateral creep force per unit creepage at ``frequency`` (Hz): ``-c_y W(iω)``."""
    b, a1, a2 = lin.relaxation[1]
    tau = 2j * np.pi * frequency / speed
    return -lin.creep_stiffness[1] * (1 + b * tau) / (1 + a1 * tau + a2 * tau**2)


def describe(lin):
    return (f"k_n {lin.normal_stiffness:.4g} N/m, mu_s {lin.sliding_coefficient:.4f}, c_x {lin.creep_stiffness[0]:.4g} N, "
            f"c_y {lin.creep_stiffness[1]:.4g} N, saturation {lin.saturation:.4f}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("map_dir", help="output folder of pipeline.py map --config studies/maps.toml")
    parser.add_argument("points", nargs="*", metavar="INDEX:WHEEL_MODEL",
                        help=f"map points (default: {' '.join(DEFAULT_POINTS)})")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    map_dir = args.map_dir
    points = args.points or DEFAULT_POINTS
    study = load_study("studies/maps.toml")
    layout = plan(study, map_dir)
    contacts = ContactCache()
    wheels = {}
    for item in points:
        index, name = item.split(":")
        index = int(index)
        overrides, config = layout["configurations"][index]
        print(f"\n== configuration {index}, {name}: {overrides}", flush=True)
        point = contacts(config)
        chunk = next(c for c in layout["chunks"] if index in c["indices"])
        wheel_dir = layout["wheels"][chunk["wheel"]][0]
        if wheel_dir not in wheels:
            modes = read_modes(wheel_dir / "wheel_modes.h5", with_shapes=True)
            wheels[wheel_dir] = WheelModels(modes, read_mesh(wheel_dir / "wheel_mesh.h5"),
                                            get_section(config, "wheel.rotation"))
        speed = config["operating"]["speed"]
        models = wheels[wheel_dir].at(speed, wheel_point(config, point))
        wheel = wheel_at_contact({name: models[name]}, point)[name]
        rail = rail_in_contact_frame(read_rail_fit(layout["rail_fits"][index]), point.rail_section_angle)
        half = case_study(config, {"contact.model": "halfspace"})
        t0 = time.perf_counter()
        lin_h = linear_contact(half, point)
        t_h = time.perf_counter() - t0
        lin_p = linear_contact(config, point)
        print(f"point law:  {describe(lin_p)}")
        print(f"half-space: {describe(lin_h)}  ({t_h:.1f} s, grid {contact_model(half, point).grid})")

        def run(label, lin, wheel=wheel, rail=rail, speed=speed):
            lam = closed_loop_eigenvalues(*wheel, rail, lin.normal_stiffness, lin.sliding_coefficient,
                                          lin.creep_stiffness, speed, None, lin.relaxation)
            in_band = (lam.imag > 0) & (np.abs(lam) / (2 * np.pi) <= rail.band[1])
            top = lam[in_band][np.argmax(lam.real[in_band])]
            tone = pole_near(lam, TONE)
            tone_text = "none" if tone is None else f"{tone.imag / (2 * np.pi):8.3f} Hz {tone.real:+8.3f} 1/s"
            print(f"  {label:42s} margin {top.real:+8.3f} 1/s at {top.imag / (2 * np.pi):8.2f} Hz | "
                  f"near {TONE:g} Hz: {tone_text}", flush=True)

        run("point law", lin_p)
        run("half-space", lin_h)
        run("half-space, mu_s of the point law", dataclasses.replace(lin_h, sliding_coefficient=lin_p.sliding_coefficient))
        run("half-space, c_y of the point law",
            dataclasses.replace(lin_h, creep_stiffness=(lin_h.creep_stiffness[0], lin_p.creep_stiffness[1])))
        run("half-space, c_x of the point law",
            dataclasses.replace(lin_h, creep_stiffness=(lin_p.creep_stiffness[0], lin_h.creep_stiffness[1])))
        run("half-space, k_n of the point law (Hertz)",
            dataclasses.replace(lin_h, normal_stiffness=lin_p.normal_stiffness))
        run("point law, mu_s of the half-space",
            dataclasses.replace(lin_p, sliding_coefficient=lin_h.sliding_coefficient))
        run("point law, c_y of the half-space",
            dataclasses.replace(lin_p, creep_stiffness=(lin_p.creep_stiffness[0], lin_h.creep_stiffness[1])))
        run("half-space, no relaxation", dataclasses.replace(lin_h, relaxation=None))
        model = contact_model(half, point)
        lin_n = linearise_halfspace_contact(model, point.normal_force, imposed_creepage(config, point),
                                            lin_p.relaxation, stick_relaxation=False)
        run("half-space, no-slip relaxation (not shortened)", lin_n)
        xi, eta, phi = imposed_creepage(config, point)
        lin_0 = linearise_halfspace_contact(model, point.normal_force, (xi, eta, 0.0), lin_h.relaxation)
        print(f"  half-space without spin: {describe(lin_0)}")
        run("half-space, spin 0", lin_0)
        # the lateral creep force's small-signal response of the transient half-space at the frequency
        # where the two relaxations differ most in the screen, against the relaxed law's -c_y W(iω)
        for frequency in sorted({round(float(f), 2) for f in FREQUENCIES.get(index, ())}):
            t0 = time.perf_counter()
            measured = transient_creep_response(model, point.normal_force, (xi, eta, phi), frequency)
            t_r = time.perf_counter() - t0
            print(f"  lateral creep response at {frequency:g} Hz: transient half-space {measured:.4g} N "
                  f"({t_r:.0f} s); shortened relaxation {creep_response(lin_h, frequency, speed):.4g} N; "
                  f"no-slip relaxation {creep_response(lin_n, frequency, speed):.4g} N; "
                  f"point law {creep_response(lin_p, frequency, speed):.4g} N", flush=True)
        for step in (3e-3, 1e-2, 3e-2):
            jac = steady_jacobian(model, point.normal_force, (xi, eta, phi), step)
            print(f"  step {step:g}: dF/dQ {np.round(jac.load_slope, 5)}, dF/d(xi, eta, phi) "
                  f"{np.array2string(jac.creep_slope, precision=4)}, slip fraction {jac.slip_fraction:.3f}")


if __name__ == "__main__":
    main()
