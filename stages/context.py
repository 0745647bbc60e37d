"""What a stage body receives: the study, its upstream artefacts and where to write."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from squealcore.artefacts import write_artefact
from squealcore.study import get_section


def key_value(study, dotted):
    """The value of a dotted configuration key of a study (None if absent)."""
    value = study
    for part in dotted.split("."):
        if not isinstance(value, dict) or part not in value:
            return None
        value = value[part]
    return value


def read_configuration(study, sections, keys=()):
    """The configuration a stage reads, as hashed and recorded: ``{section: table}`` and, if it
    reads single keys, ``{"keys": {dotted key: value}}``."""
    config = {section: get_section(study, section) for section in sections}
    if keys:
        config["keys"] = {key: key_value(study, key) for key in keys}
    return config


@dataclass
class StageContext:
    """Inputs and output of one stage run.

    Attributes
    ----------
    study : dict
        The complete, validated study.
    out_dir : Path
        Output folder of the study.
    output : Path
        The artefact this stage writes.
    inputs : dict
        Upstream stage name -> artefact path.
    schema, schema_version : str, int
        Kind and layout version of the artefact.
    params_sha256 : str
        Hash of the configuration sections the stage reads.
    input_hashes : dict
        Upstream artefact file name -> SHA-256.
    progress : bool
        Whether long loops may show a progress bar.
    sections : tuple of str
        Configuration sections the stage reads (dotted, e.g. ``"wheel.fe"``); the artefact
        records them (attribute ``config``).
    keys : tuple of str
        Single configuration keys the stage reads besides (dotted, e.g. ``"time.time_step"``);
        recorded too.
    """

    study: dict
    out_dir: Path
    output: Path
    inputs: dict = field(default_factory=dict)
    schema: str = ""
    schema_version: int = 1
    params_sha256: str = ""
    input_hashes: dict = field(default_factory=dict)
    progress: bool = True
    sections: tuple = ()
    keys: tuple = ()

    def section(self, dotted):
        """A configuration table without its sub-tables, e.g. ``ctx.section("wheel.fe")``."""
        return get_section(self.study, dotted)

    def config(self):
        """The configuration the stage reads (:func:`read_configuration` of :attr:`sections` and :attr:`keys`)."""
        return read_configuration(self.study, self.sections, self.keys)

    def writer(self):
        """Context manager writing this stage's artefact atomically with its provenance (including
        the configuration sections it reads) and checksums."""
        return write_artefact(self.output, self.schema, self.schema_version, self.params_sha256, self.input_hashes,
                              config=self.config())
