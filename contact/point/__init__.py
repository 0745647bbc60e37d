"""The point model (``contact.model = "point"``): Hertz normal spring and a transient creep-force law.

* ``model`` — :class:`~contact.point.model.PointContact`, its builders for a study and for the
  contact command, and its linearisation (the stability screen's hook);
* ``kernels`` — the compiled law (transient strips or relaxed creep law) and its Jacobian;
* ``loop`` — the compiled time loop of the interaction with this model;
* ``bundles`` — :class:`~contact.point.bundles.PointLaw`, the law's constants;
* ``fit_relaxation`` — the fit of the creep-force relaxation to the transient half-space model.

Importing this package registers the model (:mod:`contact.registry`) and nothing heavier.
"""

from contact.registry import ContactModelSpec, register

register(ContactModelSpec(
    "point", "fast point contact: Hertz normal spring, transient strips (or relaxed creep law) tangentially.",
    model_class="contact.point.model:PointContact", build="contact.point.model:for_study",
    linearise="contact.point.model:linearise_for_study",
    command="contact.point.model:for_command", fast=True))
