"""The contact-frame wheel and the Hertz stiffness that the screen (stages/screen.py) and the
report's rigid-rail stability table (stages/report.py::stability_lines) share.

References: the contact linearisation's own normal stiffness (Hertz's 3 Q / (2 δ(Q)) from the
contact model's scaled solution, another route to the same number); a rotation by the contact
angle written out (the residue R' = Q R Qᵀ with Q the rotation about x)."""

import numpy as np

from stages.config import load_study
from stages.screen import hertz_stiffness, linear_contact, screen_point, wheel_at_contact


def test_hertz_stiffness_is_the_linearised_contact_s():
    study = load_study(None, True, [])
    point = screen_point(study)
    assert hertz_stiffness(study, point) > 0
    assert np.isclose(hertz_stiffness(study, point), linear_contact(study, point).normal_stiffness, rtol=1e-9)


def test_wheel_at_contact_rotates_the_residues_about_x():
    class Point:
        contact_angle = 0.3

    rng = np.random.default_rng(2)
    poles = np.array([-1.0 + 2000.0j, -2.0 + 5000.0j])
    residues = rng.normal(size=(2, 3, 3)) + 1j * rng.normal(size=(2, 3, 3))
    out = wheel_at_contact({"stationary": (poles, residues)}, Point())
    assert np.array_equal(out["stationary"][0], poles)
    c, s = np.cos(0.3), np.sin(0.3)
    q = np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
    # rows of q: the contact frame's axes in the wheel's frame (interaction.frame's convention)
    expected = np.einsum("ij,kjl,ml->kim", q, residues, q)
    assert np.allclose(out["stationary"][1], expected, rtol=0, atol=1e-12)
