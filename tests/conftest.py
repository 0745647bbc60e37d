import os
import shutil

import pytest

# Single-threaded BLAS, as the pipeline runs it (see pipeline.py): the tests are many small
# dense problems, for which threads only add contention.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import pipeline  # noqa: E402  (after the thread settings: numpy reads them on import)
from stages import engine  # noqa: E402
from stages.config import load_study  # noqa: E402

#: Files the structural stages of a study write (the artefacts and the wheel's mesh files).
STRUCTURAL_FILES = tuple(stage.filename for stage in engine.STAGES) + ("wheel.msh", "wheel.vtu")


def copy_structures(source, target):
    """Copy the structural artefacts of the folder ``source`` into the folder ``target`` (created);
    returns ``target``. Freshness is by content hashes, so the copies are fresh where the originals are."""
    target.mkdir(parents=True, exist_ok=True)
    for name in STRUCTURAL_FILES:
        shutil.copy2(source / name, target / name)
    return target


@pytest.fixture(scope="session")
def quick_structures(tmp_path_factory):
    """The quick study's structural artefacts, built once per test session. Read-only: copy them
    (:func:`copy_structures`) into a folder of your own before running anything there. The
    structural stages do not read ``time.duration`` nor ``[contact]`` other than
    ``contact.geometry``, so studies that differ from the quick one only there find them fresh."""
    out = tmp_path_factory.mktemp("quick_structures")
    rebuilt = engine.run_structural(load_study(quick=True), out, engine.STAGES, progress=False)
    assert rebuilt == [stage.name for stage in engine.STAGES]
    return out


@pytest.fixture(scope="session")
def quick_run(quick_structures, tmp_path_factory):
    """The quick study run to the end (``pipeline.py run --quick``) once per test session, on a copy
    of :func:`quick_structures`. Read-only: copy the folder before changing anything in it."""
    out = copy_structures(quick_structures, tmp_path_factory.mktemp("quick_run"))
    assert pipeline.main(["run", "--quick", "--quiet", "--out", str(out)]) == 0
    return out


@pytest.fixture(scope="session")
def copy_quick_structures(quick_structures):
    """``copy(target)``: copies :func:`quick_structures` into the folder ``target``; returns it."""
    return lambda target: copy_structures(quick_structures, target)
