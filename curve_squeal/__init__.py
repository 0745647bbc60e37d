"""curve-squeal's Python API: studies and their results from scripts and notebooks.

A small facade over what the command line runs (``python pipeline.py run``): it loads and
validates a study, builds it in a study folder (the same stages, artefacts, study record and
lock as ``pipeline.py run``) and reads the results back as Python objects in SI units::

    import curve_squeal as cs

    study = cs.load_study(quick=True, overrides={"time.duration": 0.2})
    cs.run(study, "out-quick")
    for row in cs.summary("out-quick"):
        print(row["case_id"], row["L_F2"], row["squeal"])
    case = cs.read_case("out-quick", row["case_id"])      # time (s), force (N), creepage, ...
    wheel = cs.read_wheel("out-quick", "eulerian")        # poles (rad/s), receptance (m/N), ...

Every function raises the project's errors: :class:`InputError` for a bad argument (a study
value out of range, an unknown case or wheel model, a folder of another study), :class:`ArtefactError`
for a missing or damaged artefact, :class:`FolderError` for a fault of the folder (another run
holds its lock). Nothing here unpickles or evaluates text. See ``docs/user-guide.md``, *Python API*,
and the scripts in ``examples/``.
"""

from __future__ import annotations

from curve_squeal.api import (CaseResult, Study, WheelResponse, load_study, read_case, read_wheel, run, study_of,
                              summary)
from interaction.wheel_models import wheel_model_names
from squealcore.artefacts import ArtefactError
from squealcore.errors import InputError
from stages.engine import CasesFailed
from stages.folder import FolderBusy, FolderError

__all__ = ["load_study", "study_of", "run", "summary", "read_case", "read_wheel", "wheel_model_names", "Study",
           "CaseResult", "WheelResponse", "InputError", "ArtefactError", "FolderError", "FolderBusy", "CasesFailed"]
