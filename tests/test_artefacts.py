"""Artefact integrity and provenance: checksums, damage detection, temporary files, rebuilds.

Damage is made the way it happens: bytes changed inside a dataset's stored data (located with
h5py's storage offsets, so the test knows which dataset it hit), a dataset deleted with h5py, a
foreign HDF5 file, a directory where the file should be, an artefact of the older layout.
"""

import errno
import hashlib
import importlib.metadata
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from stages import engine
import squealcore.artefacts as artefacts
from squealcore.artefacts import (ArtefactError, add_dataset, dataset_sha256, freshness, params_hash, read_dataset,
                                  remove_stale_temporaries, write_artefact)
from squealcore.study import get_section
from stages.config import load_study
from stages.context import StageContext

ROOT = Path(__file__).resolve().parent.parent
SCHEMA, VERSION, PARAMS, INPUTS = "sample", 3, "a" * 64, {"up.h5": "b" * 64}
RNG = np.random.default_rng(7)
VALUES = {"rail/x": RNG.standard_normal(500), "moving/kernel": RNG.standard_normal((400, 3, 3)),
          "label": np.array(["first", "second"]), "scalar": 2.5}


def _write(path, config=None):
    """A sample artefact: contiguous, gzip-chunked, string and scalar datasets."""
    with write_artefact(path, SCHEMA, VERSION, PARAMS, INPUTS, config=config) as f:
        add_dataset(f, "rail/x", VALUES["rail/x"], "m")
        add_dataset(f, "moving/kernel", VALUES["moving/kernel"], "m/N", compress=True)
        add_dataset(f, "label", VALUES["label"], "")
        add_dataset(f, "scalar", VALUES["scalar"], "s")
    return path


def _fresh(path):
    return freshness(path, SCHEMA, VERSION, PARAMS, INPUTS)


def _flip(path, offset, count=16):
    """Invert ``count`` bytes of a file from ``offset`` on."""
    with open(path, "r+b") as handle:
        handle.seek(offset)
        data = handle.read(count)
        handle.seek(offset)
        handle.write(bytes(b ^ 0xFF for b in data))


def _data_offset(path, name):
    """File offset of the middle of a dataset's stored data (contiguous or first chunk)."""
    with h5py.File(path, "r") as f:
        dset = f[name]
        if dset.chunks is None:
            return dset.id.get_offset() + dset.id.get_storage_size() // 2
        chunk = dset.id.get_chunk_info(0)
        return chunk.byte_offset + chunk.size // 2


def test_intact_artefact_is_fresh_and_reads_back(tmp_path):
    path = _write(tmp_path / "a.h5")
    assert _fresh(path) == (True, "")
    with h5py.File(path, "r") as f:
        recorded = json.loads(f.attrs["checksums"])
        assert sorted(k for k in recorded if not k.startswith("@")) == sorted(VALUES)
        # the root attributes too (issue 36): provenance and whatever the writer set
        assert {"@schema", "@params_sha256", "@inputs"} <= set(recorded)
        for name, value in VALUES.items():
            data = read_dataset(f, name)
            if name == "label":
                assert list(data) == list(value)
            else:
                assert np.array_equal(data, value)
        # the checksum is that of the dtype, shape and C-order bytes (computed here independently)
        expected = hashlib.sha256(f"<f8|(500,)|".encode() + VALUES["rail/x"].astype("<f8").tobytes()).hexdigest()
        assert recorded["rail/x"] == expected == dataset_sha256(f["rail/x"])


def test_blockwise_checksum_equals_whole_array_checksum(tmp_path, monkeypatch):
    # Large datasets are hashed in blocks; the result must not depend on the block size.
    path = _write(tmp_path / "a.h5")
    with h5py.File(path, "r") as f:
        whole = dataset_sha256(f["moving/kernel"]), dataset_sha256(f["label"])
        monkeypatch.setattr(artefacts, "_BLOCK_BYTES", 100)  # 1 row of 72 bytes per block
        assert (dataset_sha256(f["moving/kernel"]), dataset_sha256(f["label"])) == whole


def test_flipped_bytes_in_contiguous_data_are_named(tmp_path):
    path = _write(tmp_path / "a.h5")
    _flip(path, _data_offset(path, "rail/x"))
    with h5py.File(path, "r") as f:  # the damage is where the test meant it to be
        assert not np.array_equal(f["rail/x"][()], VALUES["rail/x"])
    assert _fresh(path) == (False, "checksum mismatch in rail/x")


def test_flipped_bytes_in_compressed_data_are_named(tmp_path):
    path = _write(tmp_path / "a.h5")
    _flip(path, _data_offset(path, "moving/kernel"))
    fresh, reason = _fresh(path)
    assert not fresh
    assert reason in ("checksum mismatch in moving/kernel", "dataset moving/kernel unreadable (OSError)")


def test_read_dataset_names_file_and_dataset_on_damage(tmp_path):
    path = _write(tmp_path / "a.h5")
    _flip(path, _data_offset(path, "rail/x"))
    with h5py.File(path, "r") as f:
        with pytest.raises(ArtefactError, match="checksum mismatch") as err:
            read_dataset(f["rail"], "x", "m")
        assert str(path) in str(err.value) and "/rail/x" in str(err.value)
        assert read_dataset(f, "scalar", "s") == VALUES["scalar"]  # the intact ones still read


def test_overwritten_values_are_caught_on_read(tmp_path):
    path = _write(tmp_path / "a.h5")
    with h5py.File(path, "r+") as f:
        f["moving/kernel"][0, 0, 0] += 1e-12
    assert _fresh(path) == (False, "checksum mismatch in moving/kernel")
    with h5py.File(path, "r") as f:
        with pytest.raises(ArtefactError, match=r"a\.h5:/moving/kernel: checksum mismatch"):
            read_dataset(f, "moving/kernel")


def test_deleted_and_added_datasets_are_named(tmp_path):
    path = _write(tmp_path / "a.h5")
    with h5py.File(path, "r+") as f:  # attributes intact, one dataset gone, one more
        del f["rail/x"]
        f["extra"] = np.zeros(3)
    assert _fresh(path) == (False, "dataset rail/x missing; unexpected dataset extra")
    with h5py.File(path, "r") as f:
        with pytest.raises(ArtefactError, match="extra: unexpected dataset"):
            read_dataset(f, "extra")


def test_foreign_files_are_named(tmp_path):
    plain = tmp_path / "plain.h5"
    with h5py.File(plain, "w") as f:
        f["x"] = np.arange(3)
    assert _fresh(plain) == (False, "foreign HDF5 file (no schema attribute)")
    other = tmp_path / "other.h5"
    with write_artefact(other, "rail_mesh", 1, PARAMS, INPUTS) as f:
        add_dataset(f, "x", 1.0, "m")
    assert _fresh(other) == (False, "foreign artefact (schema 'rail_mesh', expected 'sample')")
    junk = tmp_path / "junk.h5"
    junk.write_bytes(os.urandom(4096))
    assert _fresh(junk) == (False, "unreadable (OSError)")


def test_directory_or_special_file_in_place_of_an_artefact(tmp_path):
    (tmp_path / "a.h5").mkdir()
    assert _fresh(tmp_path / "a.h5") == (False, "is a directory")
    assert _fresh(tmp_path / "b.h5") == (False, "missing")
    if hasattr(os, "mkfifo"):
        os.mkfifo(tmp_path / "c.h5")
        assert _fresh(tmp_path / "c.h5") == (False, "not a file")


def test_artefact_of_the_older_layout_is_stale_but_readable(tmp_path):
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:  # the layout written before checksums existed
        f.attrs.update(schema=SCHEMA, schema_version=VERSION, params_sha256=PARAMS,
                       inputs=json.dumps(INPUTS, separators=(",", ":")),
                       code_version="0.1.0", created="2026-01-01T00:00:00+00:00", complete=True)
        add_dataset(f, "rail/x", VALUES["rail/x"], "m")
    assert _fresh(path) == (False, "no checksums (older layout)")
    with h5py.File(path, "r") as f:
        assert np.array_equal(read_dataset(f, "rail/x", "m"), VALUES["rail/x"])


def test_other_reasons_come_before_the_data_check(tmp_path):
    path = _write(tmp_path / "a.h5")
    assert freshness(path, SCHEMA, VERSION, "c" * 64, INPUTS) == (False, "parameters changed")
    assert freshness(path, SCHEMA, VERSION, PARAMS, {}) == (False, "inputs changed")
    assert freshness(path, SCHEMA, VERSION + 1, PARAMS, INPUTS) == (False, f"schema version {VERSION} != {VERSION + 1}")


def test_provenance_attributes(tmp_path):
    study = load_study(quick=True)
    sections = ("wheel.fe", "time")
    ctx = StageContext(study=study, out_dir=tmp_path, output=tmp_path / "p.h5", schema=SCHEMA, schema_version=VERSION,
                       params_sha256=PARAMS, input_hashes=INPUTS, sections=sections)
    with ctx.writer() as f:
        add_dataset(f, "x", 1.0, "m")
    with h5py.File(ctx.output, "r") as f:
        attrs = dict(f.attrs)
    assert json.loads(attrs["config"]) == {s: get_section(study, s) for s in sections}
    assert "\n" in attrs["config"]  # indented: readable with h5dump / h5ls
    try:
        installed = importlib.metadata.version("curve-squeal")
    except importlib.metadata.PackageNotFoundError:
        installed = artefacts.__version__
    assert attrs["code_version"] == installed
    git = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    if git.returncode == 0 and (ROOT / ".git").exists():
        assert attrs["code_commit"] == git.stdout.strip()
    else:
        assert "code_commit" not in attrs
    assert attrs["complete"] and attrs["schema"] == SCHEMA and json.loads(attrs["inputs"]) == INPUTS


def test_fallback_version_matches_pyproject():
    with open(ROOT / "pyproject.toml", "rb") as handle:
        assert artefacts.__version__ == tomllib.load(handle)["project"]["version"]


def test_no_commit_outside_a_git_checkout(tmp_path, monkeypatch):
    monkeypatch.setattr(artefacts, "_SOURCE_ROOT", tmp_path)
    artefacts.source_commit.cache_clear()
    try:
        assert artefacts.source_commit() is None
        path = _write(tmp_path / "a.h5")
        with h5py.File(path, "r") as f:
            assert "code_commit" not in f.attrs
    finally:
        artefacts.source_commit.cache_clear()


def test_temporary_name_carries_the_process_id(tmp_path):
    with write_artefact(tmp_path / "a.h5", SCHEMA, VERSION, PARAMS) as f:
        add_dataset(f, "x", 1.0, "m")
        (name,) = os.listdir(tmp_path)
        assert name.startswith(f".a.h5.{os.getpid()}-") and name.endswith(".tmp")
        assert remove_stale_temporaries(tmp_path) == []  # a live writer's file stays
    assert os.listdir(tmp_path) == ["a.h5"]
    with artefacts.atomic_output(tmp_path / "b.png") as tmp:
        assert tmp.name.startswith(f".b.png.{os.getpid()}-") and tmp.name.endswith(".tmp.png")
        tmp.write_bytes(b"x")


def _dead_pid():
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_stale_temporaries_removed_only_when_their_process_is_gone(tmp_path):
    host = artefacts._HOST
    dead, alive = _dead_pid(), os.getpid()
    (tmp_path / "cases").mkdir()
    files = {
        "dead": tmp_path / f".rail_greens.h5.{dead}-{host}.abc123_z.tmp",
        "dead_nested": tmp_path / "cases" / f".c.h5.{dead}-{host}.k9k9k9k9.tmp",
        "dead_png": tmp_path / f".fig.png.{dead}-{host}.q1w2e3r4.tmp.png",
        "alive": tmp_path / f".wheel_greens.h5.{alive}-{host}.zzzzzzzz.tmp",
        "alive_old": tmp_path / f".wheel_modes.h5.{alive}-{host}.yyyyyyyy.tmp",
        "other_host": tmp_path / f".rail_mesh.h5.{dead}-elsewhere.xxxxxxxx.tmp",
        "legacy_old": tmp_path / ".wheel_mesh.h5.abcd1234.tmp",
        "legacy_new": tmp_path / ".report.h5.abcd1234.tmp",
        "artefact": tmp_path / "rail_greens.h5",
        "user": tmp_path / "notes.tmp",
    }
    for path in files.values():
        path.write_bytes(b"")
    two_days_ago = time.time() - 2 * 86400
    for key in ("alive_old", "legacy_old"):
        os.utime(files[key], (two_days_ago, two_days_ago))
    removed = remove_stale_temporaries(tmp_path)
    gone = {"dead", "dead_nested", "dead_png", "alive_old", "legacy_old"}
    assert sorted(removed) == sorted(files[k] for k in gone)
    assert all(files[k].exists() != (k in gone) for k in files)
    assert remove_stale_temporaries(tmp_path / "absent") == []


def test_stale_temporary_removal_survives_a_failing_file(tmp_path, monkeypatch):
    dead = _dead_pid()
    first = tmp_path / f".a.h5.{dead}-{artefacts._HOST}.aaaaaaaa.tmp"
    second = tmp_path / f".b.h5.{dead}-{artefacts._HOST}.bbbbbbbb.tmp"
    for path in (first, second):
        path.write_bytes(b"")
    (tmp_path / f".d.h5.{dead}-{artefacts._HOST}.dddddddd.tmp").mkdir()  # not a file: left alone
    real_unlink = Path.unlink

    def unlink(self, *args, **kwargs):
        if self == first:
            raise PermissionError("read-only")
        return real_unlink(self, *args, **kwargs)

    monkeypatch.setattr(Path, "unlink", unlink)
    assert remove_stale_temporaries(tmp_path) == [second]
    assert first.exists() and not second.exists()


# --- end to end: the pipeline notices a damaged artefact and rebuilds it ----------------------

RAIL = engine.STAGE_BY_NAME["rail-greens"]


@pytest.fixture(scope="module")
def rail_built(tmp_path_factory):
    out = tmp_path_factory.mktemp("rail")
    rebuilt = engine.run(load_study(quick=True), out, until="rail-greens", progress=False)
    # the rail's Green's functions are computed at the contact point of the contact geometry
    assert rebuilt == ["contact-geometry", "rail-mesh", "rail-greens"]
    return out


def _rail_status(out):
    return {name: (fresh, reason) for name, fresh, reason in engine.status(load_study(quick=True), out)}


def test_rail_greens_records_the_sections_it_read(rail_built):
    study = load_study(quick=True)
    with h5py.File(rail_built / RAIL.filename, "r") as f:
        config = json.loads(f.attrs["config"])
        assert config == engine.stage_params(RAIL, study)
        assert params_hash(config) == f.attrs["params_sha256"]  # the stored text is what was hashed


def test_damaged_rail_greens_is_reported_and_rebuilt(tmp_path, rail_built):
    out = tmp_path / "o"
    shutil.copytree(rail_built, out)
    target = out / RAIL.filename
    _flip(target, _data_offset(target, "wavenumbers"))
    assert _rail_status(out)["rail-greens"] == (False, "checksum mismatch in wavenumbers")
    assert _rail_status(out)["rail-mesh"] == (True, "")
    study = load_study(quick=True)
    assert engine.run(study, out, until="rail-greens", progress=False) == ["rail-greens"]
    assert _rail_status(out)["rail-greens"] == (True, "")
    with h5py.File(target, "r") as f, h5py.File(rail_built / RAIL.filename, "r") as g:
        assert np.array_equal(f["wavenumbers"][()], g["wavenumbers"][()])


def test_rail_greens_without_a_dataset_is_stale(tmp_path, rail_built):
    # Attributes intact, a dataset deleted: stale, so ``run`` rebuilds it (run_structural
    # rebuilds exactly the stages that ``inspect`` finds stale; the rebuild itself is tested above).
    out = tmp_path / "o"
    shutil.copytree(rail_built, out)
    with h5py.File(out / RAIL.filename, "r+") as f:
        del f["moving/kernel"]
    assert _rail_status(out)["rail-greens"] == (False, "dataset moving/kernel missing")
    assert engine.inspect(RAIL, load_study(quick=True), out)[:2] == (False, "dataset moving/kernel missing")


def test_status_command_names_the_damage(tmp_path, rail_built):
    out = tmp_path / "o"
    shutil.copytree(rail_built, out)
    _flip(out / RAIL.filename, _data_offset(out / RAIL.filename, "frequency"))
    completed = subprocess.run([sys.executable, str(ROOT / "pipeline.py"), "status", "--quick", "--quiet", "--out",
                                str(out)], capture_output=True, text=True, cwd=tmp_path,
                               env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert completed.returncode == 1, completed.stderr  # status: 1 when something needs a rebuild
    (line,) = [row for row in completed.stdout.splitlines() if row.startswith("rail-greens ")]
    assert "stale" in line and "checksum mismatch in frequency" in line


def test_a_file_that_cannot_be_created_is_named_not_its_temporary(tmp_path, monkeypatch):
    """An OSError from creating the temporary file names the file asked for (the CLI prints it as `path: reason`)."""
    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied", str(tmp_path / ".fields.h5.123-host.abc.tmp.h5"))

    monkeypatch.setattr(artefacts.tempfile, "mkstemp", refuse)
    target = tmp_path / "fields.h5"
    with pytest.raises(OSError) as err:
        with artefacts.atomic_output(target):
            pass
    assert err.value.filename == str(target) and "Permission denied" in err.value.strerror
    assert not list(tmp_path.iterdir())


# --------------------------------------------------------------------------- issue 36: attributes, full disk


def test_an_edited_root_attribute_is_named(tmp_path):
    path = tmp_path / "a.h5"
    with write_artefact(path, SCHEMA, VERSION, PARAMS, INPUTS) as f:
        add_dataset(f, "x", np.arange(3.0), "m")
        f.attrs["L_F2"] = -31.5
        f.attrs["squeal"] = False
    assert _fresh(path) == (True, "")
    with h5py.File(path, "r+") as f:
        f.attrs["L_F2"] = 123.4
        f.attrs["squeal"] = True
    fresh, reason = _fresh(path)
    assert not fresh and "attribute L_F2 changed" in reason and "attribute squeal changed" in reason
    with h5py.File(path, "r+") as f:
        f.attrs["L_F2"] = -31.5
        f.attrs["squeal"] = False
        f.attrs["note"] = "added"
        del f.attrs["created"]
    fresh, reason = _fresh(path)
    assert "attribute created missing" in reason and "unexpected attribute note" in reason


@pytest.mark.parametrize("number", [errno.ENOSPC, errno.EDQUOT, errno.EACCES])
def test_a_full_disk_while_writing_names_the_artefact_and_publishes_nothing(tmp_path, monkeypatch, number):
    (tmp_path / "a.h5").write_bytes(b"old")  # an earlier version stays as it was

    def write_half(tmp_name, image):
        with open(tmp_name, "wb") as handle:
            handle.write(image[: len(image) // 2])
        raise OSError(number, os.strerror(number))

    monkeypatch.setattr(artefacts, "write_image", write_half)
    with pytest.raises(OSError) as caught:
        _write(tmp_path / "a.h5")
    assert caught.value.errno == number and caught.value.filename == str(tmp_path / "a.h5")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.h5"]  # no temporary file left
    assert (tmp_path / "a.h5").read_bytes() == b"old"


def test_hdf5_errors_of_a_full_disk_become_one_os_error(tmp_path):
    fault = artefacts.resource_fault(RuntimeError("Can't write data (file write failed: time = x, filename = 'y', "
                                                  "file descriptor = 5, errno = 28, error message = 'No space left on "
                                                  "device')"), tmp_path / "a.h5")
    assert fault.errno == errno.ENOSPC and fault.filename == str(tmp_path / "a.h5")
    assert artefacts.resource_fault(ValueError("shape mismatch"), tmp_path / "a.h5") is None


def test_a_file_written_onto_a_full_disk_is_not_published(tmp_path, monkeypatch):
    monkeypatch.setattr(artefacts, "free_bytes", lambda folder: 0)  # gmsh says nothing when its write fails
    with pytest.raises(OSError) as caught:
        with artefacts.atomic_output(tmp_path / "wheel.msh") as partial:
            partial.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n12 3")
    assert caught.value.errno == errno.ENOSPC and "incomplete" in caught.value.strerror
    assert list(tmp_path.iterdir()) == []
