"""The half-space model (``contact.model = "halfspace"``): Kalker-type non-steady rolling contact on a grid.

One folder, one model, as CONTACT keeps one module per problem:

* ``model`` — :class:`~contact.halfspace.model.HalfspaceContact`, the model the time domain calls
  per step, and its builders for a study and for the contact command;
* ``normal`` / ``tangential`` / ``steady`` / ``transient_fft`` — the normal problem, the
  tangential problems (steady, transient, shift), steady rolling by sweeps on the rolling
  operator, and the large-patch transient solver;
* ``influence`` / ``fft_products`` — influence coefficients of the half-space and their
  matrix-free FFT products;
* ``linearise`` — the model linearised about steady rolling (the stability screen's hook);
* ``loop`` — the compiled time loop of the interaction with this model;
* ``bundles`` — the typed named tuples its compiled kernels take;
* compiled kernels by job: ``normal_kernels``, ``tangential_kernels``, ``rolling_kernels``,
  ``influence_kernels``, ``local_sweep_kernels``, ``anderson_kernels``.

Importing this package registers the model (:mod:`contact.registry`) and nothing heavier: the
hooks name their modules and are imported at first use.
"""

from contact.registry import ContactModelSpec, register

register(ContactModelSpec(
    "halfspace", "Kalker-type transient rolling contact on a grid of the elastic half-space, as in the paper.",
    model_class="contact.halfspace.model:HalfspaceContact", build="contact.halfspace.model:for_study",
    linearise="contact.halfspace.linearise:linearise_for_study",
    command="contact.halfspace.model:for_command", kinds=("steady", "transient", "shift"),
    traction_fields=True, solves_on_grid=True))
