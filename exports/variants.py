"""The structural variant an export reads (``pipeline.py export modes|receptances|rail --variant LABEL``).

A study whose sweep changes structural parameters (the wheel's radius, its tread, the rail, ...)
keeps each variant's structural artefacts in ``OUT/variants/<label>-<8 hex digits>``
(:func:`stages.engine.variant_label`); a study with one structure keeps them in ``OUT``. The
exports of wheel modes, receptances and rail waves read one variant's artefacts: this module
picks its folder from ``--variant``, and says which variants there are when the choice is
missing or wrong.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from squealcore.errors import InputError
from stages import engine

#: Export targets that read one variant's structural artefacts (``case`` finds its case's
#: variant itself, ``xdmf`` writes sidecars in every variant folder).
VARIANT_TARGETS = ("modes", "receptances", "rail")


@dataclass(frozen=True)
class Variant:
    """The structural variant an export reads.

    Attributes
    ----------
    label : str
        Folder name under ``OUT/variants`` (``""`` for a study with one structure).
    folder : Path
        Folder of its structural artefacts (``OUT`` for a study with one structure).
    study : dict
        The validated study of the variant (the sweep's structural values applied).
    siblings : tuple of Path
        Folders of all the study's variants (the engine copies an artefact from one of them
        instead of rebuilding it, when one has it fresh for the same parameters).
    """

    label: str
    folder: Path
    study: dict
    siblings: tuple = ()


def study_variants(study, out_dir):
    """The structural variants of a study, ``{label: Variant}`` in sweep order (empty: one structure)."""
    first = {}
    for case in engine.plan_cases(study, out_dir):
        if case.variant_label:
            first.setdefault(case.variant_label, case)
    siblings = tuple(Path(case.variant_dir) for case in first.values())
    return {label: Variant(label, Path(case.variant_dir), case.study, siblings) for label, case in first.items()}


def choose_variant(study, out_dir, target, label=None):
    """The variant whose artefacts export ``target`` reads.

    Parameters
    ----------
    study : dict
        The validated study.
    out_dir : Path
        Study folder.
    target : str
        Export target (``modes``, ``receptances``, ``rail``, ``case``, ``xdmf``).
    label : str, optional
        ``--variant``: a folder name under ``OUT/variants`` (``rolling_radius=0.37-1a2b3c4d``) or
        its readable part before the hash (``rolling_radius=0.37``) when only one variant has it.

    Returns
    -------
    Variant
        For a study with one structure, or a target that reads no single variant: label ``""``,
        folder ``out_dir``.

    Raises
    ------
    InputError
        (field ``--variant``) if the study has variants and none or an unknown one is chosen,
        if one is chosen for a study with one structure, or for a target that reads no single
        variant; the message lists the study's variants.
    """
    if target not in VARIANT_TARGETS:
        if label is not None:
            raise InputError("--variant", f"applies to export {', '.join(VARIANT_TARGETS)} only ('case' finds its "
                                          f"case's variant, 'xdmf' writes every variant's sidecars), not to "
                                          f"{target!r}")
        return Variant("", Path(out_dir), study)
    variants = study_variants(study, out_dir)
    if not variants:
        if label is not None:
            raise InputError("--variant", f"the study has one structure (its artefacts are in {out_dir}), no "
                                          f"variants: leave --variant out (got {label!r})")
        return Variant("", Path(out_dir), study)
    listing = ", ".join(variants)
    if label is None:
        raise InputError("--variant", f"the study's sweep has {len(variants)} structural variants; choose one with "
                                      f"--variant LABEL: {listing}")
    if label in variants:
        return variants[label]
    readable = [name for name in variants if name.rsplit("-", 1)[0] == label]
    if len(readable) == 1:
        return variants[readable[0]]
    if readable:
        raise InputError("--variant", f"{label!r} is the readable part of several variants; give the whole "
                                      f"label: {', '.join(readable)}")
    raise InputError("--variant", f"unknown variant {label!r}; the study's variants: {listing}")
