"""What a stage body receives: the study, its upstream artefacts and where to write."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from squealcore.artefacts import write_artefact
from squealcore.study import get_section


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

    def section(self, dotted):
        """A configuration table without its sub-tables, e.g. ``ctx.section("wheel.fe")``."""
        return get_section(self.study, dotted)

    def config(self):
        """The configuration the stage reads: ``{section: table}`` for each of :attr:`sections`."""
        return {section: self.section(section) for section in self.sections}

    def writer(self):
        """Context manager writing this stage's artefact atomically with its provenance (including
        the configuration sections it reads) and checksums."""
        return write_artefact(self.output, self.schema, self.schema_version, self.params_sha256, self.input_hashes,
                              config=self.config())
