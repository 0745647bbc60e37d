"""Exports that users' own tools open (``pipeline.py export <target>``).

One module per job; this one gathers their entry points:

- :func:`export_receptances` (``exports/receptances.py``): wheel and rail receptances as
  CSV tables;
- :func:`export_modes` (``exports/modes.py``): the wheel's mode shapes as VTU;
- :func:`export_rail` (``exports/rail.py``): rail section mesh and wave shapes as VTU;
- :func:`export_case` (``exports/case.py``): a case's time histories as CSV and, for
  chosen steps, its contact tractions as VTU (:func:`write_traction_vtu`,
  :func:`case_snapshots`);
- :func:`write_xdmf_sidecars` (``exports/xdmf.py``): XDMF files next to the HDF5 artefacts;
- :func:`choose_variant` (``exports/variants.py``): the structural variant (``--variant``)
  whose artefacts the modes, receptances and rail exports read.

CSV tables are written by ``squealcore/csv_tables.py`` (``#`` comment header, exact numbers).
"""

from __future__ import annotations

from exports.case import case_snapshots, export_case, write_traction_vtu
from exports.modes import export_modes, hex_node_shapes
from exports.rail import export_rail
from exports.receptances import export_receptances
from exports.variants import VARIANT_TARGETS, choose_variant, study_variants
from exports.xdmf import write_xdmf_sidecars

__all__ = ["export_receptances", "export_modes", "export_rail", "export_case", "write_xdmf_sidecars",
           "write_traction_vtu", "case_snapshots", "hex_node_shapes", "choose_variant", "study_variants",
           "VARIANT_TARGETS"]
