"""HDF5 output of contact solutions (written atomically: temporary file, then os.replace)."""

from __future__ import annotations

import json
import os
import tempfile
from datetime import datetime, timezone

import h5py
import numpy as np

__all__ = ["write_results"]

SCHEMA = "contact"
SCHEMA_VERSION = 1


def _dataset(group, name, data, units):
    ds = group.create_dataset(name, data=np.asarray(data))
    ds.attrs["units"] = units
    return ds


def write_results(path, results, config: dict):
    """Write a sequence of :class:`ContactResult` to HDF5.

    Datasets (step index first): ``force`` (n, 3) N, ``spin_moment`` (n,) N m, ``pmax`` (n,) Pa,
    ``n_contact/n_stick/n_slip`` (n,) 1, and for the half-space model ``x`` (nx,) m, ``y`` (ny,)
    m, ``pressure`` (n, nx, ny) Pa, ``traction`` (n, nx, ny, 2) Pa, ``status`` (n, nx, ny) 1
    (0 exterior, 1 stick, 2 slip).
    """
    path = os.path.abspath(path)
    folder = os.path.dirname(path)
    fd, tmp = tempfile.mkstemp(suffix=".h5.tmp", dir=folder)
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["schema"] = SCHEMA
            f.attrs["schema_version"] = SCHEMA_VERSION
            f.attrs["config"] = json.dumps(config, sort_keys=True)
            f.attrs["created"] = datetime.now(timezone.utc).isoformat()
            _dataset(f, "force", [r.force for r in results], "N")
            _dataset(f, "spin_moment", [r.spin_moment for r in results], "N m")
            _dataset(f, "pmax", [r.diagnostics.pmax for r in results], "Pa")
            for key in ("n_contact", "n_stick", "n_slip"):
                _dataset(f, key, [getattr(r.diagnostics, key) for r in results], "1")
            if results and results[0].fields is not None:
                fl = results[0].fields
                _dataset(f, "x", fl.x, "m")
                _dataset(f, "y", fl.y, "m")
                _dataset(f, "pressure", [r.fields.pressure for r in results], "Pa")
                _dataset(f, "traction", [r.fields.traction for r in results], "Pa")
                _dataset(f, "status", np.array([r.fields.status for r in results], np.int8), "1")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
