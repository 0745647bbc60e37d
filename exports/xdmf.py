"""XDMF sidecars: ParaView opens the HDF5 artefacts' meshes and fields directly, without copies.

:func:`write_xdmf_sidecars` writes XDMF 3 files (XML that points into the HDF5 files; paths are
relative, so a study folder can be moved as a whole) next to the artefacts of a study folder and
of each of its ``variants/<label>`` folders:

``wheel_mesh.xdmf``
    the 3D wheel: topology ``Hexahedron_20`` from ``wheel_mesh.h5:/hex20/cells``, geometry from
    ``/hex20/nodes`` (m). The artefact's node order is the VTK (Abaqus C3D20) order
    (docs/conventions.md); VTK's XDMF 3 reader (ParaView) copies ``Hexahedron_20`` connectivity
    unchanged into ``VTK_QUADRATIC_HEXAHEDRON`` cells, so that order is the one XDMF needs.
``wheel_modes.xdmf``
    (hex20 solver only) the mode shapes as a temporal collection on that mesh: "time" k is mode
    k (1-based), with the point vector ``mode_shape`` (m/sqrt(kg)) = ``wheel_modes.h5:/shapes``
    [k-1] (an XDMF hyperslab) and the grid values ``frequency_Hz`` and ``nodal_diameters``; each
    grid is named like the columns of ``pipeline.py export modes`` (``mode_003_396.4Hz_n2_axial``).
    The axisymmetric solver stores section amplitudes, not 3D shapes: then no file is written
    and ``pipeline.py export modes`` gives a VTU of the expanded shapes.
``rail_mesh.xdmf``
    the rail cross-section: ``Quadrilateral_8`` or ``Triangle_6`` cells from
    ``rail_mesh.h5:/section/cells``, geometry type ``XY`` from ``/section/nodes``, so ParaView's
    X and Y are the rail's y (lateral) and z (up), in m.

No sidecar for the cases: their histories are one value per time step of a single contact point
(about 10^5 steps), which XDMF can express only as a temporal collection of one grid per step,
an XML file of tens of megabytes that ParaView parses step by step; ``pipeline.py export case``
writes them as a CSV table instead, which plotting tools read directly.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from pathlib import Path

from squealcore.artefacts import atomic_output, open_artefact, read_dataset
from exports.modes import mode_name
from stages.wheel import read_modes

logger = logging.getLogger(__name__)

XDMF_TYPES = {"f": "Float", "i": "Int", "u": "UInt"}
"""numpy dtype kind -> XDMF ``DataType``."""

CELL_TYPES = {20: "Hexahedron_20", 8: "Quadrilateral_8", 6: "Triangle_6"}
"""Nodes per cell of the artefacts' meshes -> XDMF topology type."""


def _dims(shape):
    return " ".join(str(int(n)) for n in shape)


def hdf_item(parent, dataset):
    """Append a ``DataItem`` pointing at an h5py dataset (path relative to the XDMF file)."""
    item = ET.SubElement(parent, "DataItem", Dimensions=_dims(dataset.shape), DataType=XDMF_TYPES[dataset.dtype.kind],
                         Precision=str(dataset.dtype.itemsize), Format="HDF")
    item.text = f"{Path(dataset.file.filename).name}:{dataset.name}"
    return item


def hyperslab_item(parent, dataset, index):
    """Append a ``HyperSlab`` ``DataItem`` selecting ``dataset[index]`` along the first axis."""
    shape = dataset.shape
    part = (1,) + tuple(shape[1:])
    item = ET.SubElement(parent, "DataItem", ItemType="HyperSlab", Dimensions=_dims(part), Type="HyperSlab")
    selection = ET.SubElement(item, "DataItem", Dimensions=f"3 {len(shape)}", DataType="Int", Precision="8",
                              Format="XML")
    start = (index,) + (0,) * (len(shape) - 1)
    selection.text = " ".join(_dims(row) for row in (start, (1,) * len(shape), part))
    hdf_item(item, dataset)
    return item


def _grid(parent, name, cells, nodes, geometry_type):
    grid = ET.SubElement(parent, "Grid", Name=name, GridType="Uniform")
    topology = ET.SubElement(grid, "Topology", TopologyType=CELL_TYPES[cells.shape[1]],
                             NumberOfElements=str(cells.shape[0]))
    hdf_item(topology, cells)
    hdf_item(ET.SubElement(grid, "Geometry", GeometryType=geometry_type), nodes)
    return grid


def _document():
    root = ET.Element("Xdmf", Version="3.0")
    return root, ET.SubElement(root, "Domain")


def _write(root, path):
    ET.indent(root)
    with atomic_output(path) as tmp:
        ET.ElementTree(root).write(tmp, encoding="utf-8", xml_declaration=True)
    return Path(path)


def wheel_mesh_xdmf(folder):
    """Write ``wheel_mesh.xdmf`` for ``folder/wheel_mesh.h5``; returns its path."""
    root, domain = _document()
    with open_artefact(folder / "wheel_mesh.h5", "wheel_mesh", 1) as f:
        _grid(domain, "wheel", f["hex20/cells"], f["hex20/nodes"], "XYZ")
    return _write(root, folder / "wheel_mesh.xdmf")


def wheel_modes_xdmf(folder):
    """Write ``wheel_modes.xdmf`` for hex20 modes in ``folder``; returns its path, or None (with a
    log message) for axisymmetric modes."""
    modes = read_modes(folder / "wheel_modes.h5")
    if modes["solver"] != "hex20":
        logger.info("%s: no wheel_modes.xdmf: the %s solver stores section amplitudes, not 3D shapes; "
                    "`pipeline.py export modes` writes the expanded shapes as VTU", folder, modes["solver"])
        return None
    root, domain = _document()
    collection = ET.SubElement(domain, "Grid", Name="wheel_modes", GridType="Collection", CollectionType="Temporal")
    with open_artefact(folder / "wheel_mesh.h5", "wheel_mesh", 1) as mesh, \
            open_artefact(folder / "wheel_modes.h5", "wheel_modes", 1) as f:
        shapes = f["shapes"]
        if shapes.shape[:2] != (modes["frequency"].size, mesh["hex20/nodes"].shape[0]):
            raise ValueError(f"{f.filename}: shapes {shapes.shape} do not match the modes and the hex20 mesh")
        for k in range(modes["frequency"].size):
            grid = _grid(collection, mode_name(modes, k), mesh["hex20/cells"], mesh["hex20/nodes"], "XYZ")
            ET.SubElement(grid, "Time", Value=str(k + 1))
            attribute = ET.SubElement(grid, "Attribute", Name="mode_shape", AttributeType="Vector", Center="Node")
            hyperslab_item(attribute, shapes, k)
            for name, dataset in (("frequency_Hz", f["frequency"]), ("nodal_diameters", f["nodal_diameters"])):
                attribute = ET.SubElement(grid, "Attribute", Name=name, AttributeType="Scalar", Center="Grid")
                hyperslab_item(attribute, dataset, k)
    return _write(root, folder / "wheel_modes.xdmf")


def rail_mesh_xdmf(folder):
    """Write ``rail_mesh.xdmf`` for ``folder/rail_mesh.h5``; returns its path."""
    root, domain = _document()
    with open_artefact(folder / "rail_mesh.h5", "rail_mesh", 1) as f:
        read_dataset(f, "section/nodes", "m", (None, 2))
        _grid(domain, "rail_section", f["section/cells"], f["section/nodes"], "XY")
    return _write(root, folder / "rail_mesh.xdmf")


SIDECARS = (("wheel_mesh.h5", wheel_mesh_xdmf), ("wheel_modes.h5", wheel_modes_xdmf), ("rail_mesh.h5", rail_mesh_xdmf))
"""(artefact, writer of its sidecar)."""


def write_xdmf_sidecars(out_dir):
    """Write XDMF sidecars next to the HDF5 artefacts of a study folder and its variant folders.

    Parameters
    ----------
    out_dir : Path
        Study folder.

    Returns
    -------
    list of Path
        The XDMF files written (artefacts that are missing are skipped; see the module docstring
        for what each file holds and why the cases have none).
    """
    out_dir = Path(out_dir)
    folders = [out_dir] + sorted(p for p in (out_dir / "variants").glob("*") if p.is_dir())
    written = []
    for folder in folders:
        for artefact, writer in SIDECARS:
            if (folder / artefact).exists():
                path = writer(folder)
                if path is not None:
                    written.append(path)
    logger.info("wrote %d XDMF sidecars in %s", len(written), out_dir)
    return written

