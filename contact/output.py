"""HDF5 output of contact solutions (an artefact of kind ``contact``, written atomically)."""

from __future__ import annotations

import numpy as np

from squealcore.artefacts import add_dataset, canonical_json, params_hash, write_artefact

__all__ = ["write_results", "SCHEMA", "SCHEMA_VERSION"]

SCHEMA = "contact"
SCHEMA_VERSION = 2
"""Layout version; 2: written by :func:`squealcore.artefacts.write_artefact` (provenance attributes,
``params_sha256`` of the resolved case), ``config`` the resolved case."""


def write_results(path, results, config: dict):
    """Write a sequence of :class:`ContactResult` to HDF5.

    Parameters
    ----------
    path : str or Path
        The file.
    results : sequence of ContactResult
        One result per step.
    config : dict
        The resolved case (:attr:`contact.config.Case.config`), stored as canonical
        JSON in the attribute ``config``; its hash is ``params_sha256``.

    Notes
    -----
    Datasets (step index first): ``force`` (n, 3) N, ``spin_moment`` (n,) N m, ``pmax`` (n,) Pa,
    ``n_contact/n_stick/n_slip`` (n,) 1, and for the half-space model ``x`` (nx,) m, ``y`` (ny,)
    m, ``pressure`` (n, nx, ny) Pa, ``traction`` (n, nx, ny, 2) Pa, ``status`` (n, nx, ny) 1
    (0 exterior, 1 stick, 2 slip).
    """
    with write_artefact(path, SCHEMA, SCHEMA_VERSION, params_hash(config), {}) as f:
        f.attrs["config"] = canonical_json(config)
        add_dataset(f, "force", [r.force for r in results], "N")
        add_dataset(f, "spin_moment", [r.spin_moment for r in results], "N m")
        add_dataset(f, "pmax", [r.diagnostics.pmax for r in results], "Pa")
        for key in ("n_contact", "n_stick", "n_slip"):
            add_dataset(f, key, [getattr(r.diagnostics, key) for r in results], "1")
        if results and results[0].fields is not None:
            fields = results[0].fields
            add_dataset(f, "x", fields.x, "m")
            add_dataset(f, "y", fields.y, "m")
            add_dataset(f, "pressure", [r.fields.pressure for r in results], "Pa")
            add_dataset(f, "traction", [r.fields.traction for r in results], "Pa")
            add_dataset(f, "status", np.array([r.fields.status for r in results], np.int8), "1")
