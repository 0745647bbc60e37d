"""Steady creep forces of a contact: the project's point contact law.

The force of a contact is :meth:`contact.point.model.PointContact.steady_force`: Kalker's
linear theory (coefficients for the contact's a/b) saturated by the Shen-Hedrick-Elkins law at
μ N, built through the contact registry's model classes (``contact.factory``) with the
Hertz solution of the contact's curvatures. Its steady force is checked against the project's
steady half-space solver in ``tests/test_contact_point.py`` and, at a curving operating point,
in ``tests/test_curving.py``. One model is built per distinct contact geometry and friction and
reused (the load enters the law through the Hertz scaling).

The friction is a coefficient μ (Coulomb), or a :class:`~contact.params.Friction` with a
characteristic of the sliding speed (contact/friction_law.py): the point law then saturates at μ
of the contact's sliding speed ``V |(ξ, η)|``, V the rolling speed the law was made with
(:class:`CreepLaw`'s ``speed``; issue 35 item 4).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from contact.factory import create_model
from contact.hertz import hertz_from_curvatures
from contact.params import Friction, Material

from .geometry import ContactGeometry

__all__ = ["CreepLaw", "STEEL", "REFERENCE_LOAD"]

#: Steel on steel (E = 210 GPa, ν = 0.3), as the contact-geometry stage.
STEEL = Material.from_young(210e9, 0.3)
#: Normal load of the Hertz solution a model is built at (N); the law scales it to the actual load.
REFERENCE_LOAD = 50e3


class _RelaxationTableNote(logging.Filter):
    """Drops the point model's note that a/b lies outside its *transient* relaxation table: the
    steady law used here does not use that table (flange contacts have a/b up to about 10)."""

    def filter(self, record):
        return "relaxation table" not in record.getMessage()


class CreepLaw:
    """Steady creep forces of contacts, with one point-contact model per geometry and friction.

    Parameters
    ----------
    speed : float
        Rolling speed V, m/s, > 0: the contacts' sliding speed is ``V |(ξ, η)|`` (it matters only
        for a friction characteristic of the sliding speed).
    """

    def __init__(self, speed: float = 1.0):
        self._models = {}
        self.speed = float(speed)

    def model(self, contact: ContactGeometry, mu):
        """The steady point-contact model of a contact geometry and friction (cached): ``mu`` a
        coefficient (-) or a :class:`~contact.params.Friction`."""
        a, b = contact.hertz_curvatures()
        key = (a, b, mu)
        model = self._models.get(key)
        if model is None:
            hertz = hertz_from_curvatures(a, b, REFERENCE_LOAD, STEEL.contact_modulus)
            note = _RelaxationTableNote()
            point_log = logging.getLogger("contact.point.model")
            point_log.addFilter(note)
            try:
                friction = mu if isinstance(mu, Friction) else Friction(mu)
                model = create_model("point", material=STEEL, friction=friction, hertz=hertz, kind="steady",
                                     speed=self.speed, time_step=1e-4)
            finally:
                point_log.removeFilter(note)
            self._models[key] = model
        return model

    def force(self, contact: ContactGeometry, mu, normal_force: float, creepage) -> np.ndarray:
        """(Fx, Fy) (N) on the wheel in its contact frame (``mu`` as :meth:`model`); zero for μ = 0 or no load."""
        static = mu.static if isinstance(mu, Friction) else mu
        if static <= 0.0 or not normal_force > 0.0 or not math.isfinite(normal_force):
            return np.zeros(2)
        return self.model(contact, mu).steady_force(normal_force, creepage)

    def semi_axes(self, contact: ContactGeometry, mu: float, normal_force: float) -> tuple[float, float]:
        """Hertz semi-axes (a, b) (m) at a normal force (N)."""
        if not normal_force > 0.0:
            return 0.0, 0.0
        a, b = contact.hertz_curvatures()
        h = hertz_from_curvatures(a, b, float(normal_force), STEEL.contact_modulus)
        return h.a, h.b
