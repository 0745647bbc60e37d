"""Measured tread profile files (issue 33, item 2): the two-column text file, the variants of it
that exports produce, and one clear error line per problem (field, file, line, what is wrong, a
short escaped excerpt at most; exit status 2 from the command line)."""

import numpy as np
import pytest

import pipeline
from mesh.wheel_section import WheelParams, tread_profile
from profiles.curve import EXCERPT_CHARS, MAX_FILE_BYTES, read_profile
from squealcore.errors import InputError

#: A 1:40 cone without flange, y from the flange back and height above the tape circle (mm).
CONE_MM = [(5.0 * k, -(5.0 * k - 70.0) / 40.0) for k in range(27)]


def _write(tmp_path, name, text, mode="w"):
    path = tmp_path / name
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, newline="")
    return path


def _cone(sep=" ", eol="\n", units="mm"):
    rows = [f"{y:g}{sep}{z:g}" for y, z in CONE_MM]
    return eol.join([f"# units: {units}", "# y z", *rows]) + eol


@pytest.mark.parametrize("name, text", [
    ("blanks.txt", _cone(" ")),
    ("tabs.txt", _cone("\t")),
    ("comma.csv", _cone(", ")),
    ("semicolon.csv", _cone(";")),
    ("windows.txt", _cone(" ", "\r\n")),
    ("bom.txt", "\ufeff" + _cone(" ")),
    ("metres.txt", "\n".join(f"{y * 1e-3:.6f} {z * 1e-3:.8f}  # point" for y, z in CONE_MM) + "\n"),
])
def test_accepted_two_column_variants(tmp_path, name, text):
    profile = read_profile(_write(tmp_path, name, text))
    expected = np.array(CONE_MM) * 1e-3
    np.testing.assert_allclose(profile.y, expected[:, 0], atol=1e-12)
    np.testing.assert_allclose(profile.z, expected[:, 1], atol=1e-9)


@pytest.mark.parametrize("text, line, problem", [
    ("# units: mm\n0 1\n5 0.9\n10 0,8,1\n15 0.7\n", 4, "expected 2 columns"),
    ("0 0.001\n0.005 n/a\n0.01 0\n0.015 0\n", 2, "not a number"),
    ("0 0.001\n0.005 0\n0.01 inf\n0.015 0\n", 3, "non-finite"),
    ("0 0\n0.01 0.001\n# comment\n0.005 0.002\n0.02 0.0\n", 4, "non-monotonic"),
    ("# units: inch\n0 0\n1 1\n2 0\n3 0\n", 1, "units must be one of"),
    ("Profile export v2 by SomeDevice\n0 0\n1 1\n2 0\n3 0\n", 1, "header lines must start with #"),
])
def test_errors_name_the_line_and_the_problem(tmp_path, text, line, problem):
    path = _write(tmp_path, "bad.txt", text)
    with pytest.raises(InputError) as err:
        read_profile(path)
    assert err.value.field == str(path)
    assert f"line {line}:" in err.value.message and problem in err.value.message


def test_a_long_or_hostile_line_is_quoted_short_and_escaped(tmp_path):
    hostile = "0.01 \x1b[31m" + "A" * 5000
    path = _write(tmp_path, "bad.txt", f"0 0\n{hostile}\n0.02 0\n0.03 0\n")
    with pytest.raises(InputError) as err:
        read_profile(path)
    message = err.value.message
    assert "line 2:" in message and "\x1b" not in message and "\\x1b" in message
    assert len(message) < 100 + EXCERPT_CHARS and "A" * (EXCERPT_CHARS + 1) not in message


def test_binary_empty_and_huge_files_are_refused(tmp_path):
    with pytest.raises(InputError, match=r"line 3: not a text file \(byte 8 is not UTF-8\)"):
        read_profile(_write(tmp_path, "binary.whl", b"0 0\n1 1\n\xff\xfe\x00\x01"))
    with pytest.raises(InputError, match="no data lines"):
        read_profile(_write(tmp_path, "empty.txt", "# nothing\n\n"))
    with pytest.raises(InputError, match="too few points"):
        read_profile(_write(tmp_path, "short.txt", "0 0\n1 1\n2 0\n"))
    big = _write(tmp_path, "big.txt", "")
    with big.open("wb") as f:
        f.truncate(MAX_FILE_BYTES + 1)
    with pytest.raises(InputError, match="more than the"):
        read_profile(big)


def test_tread_profile_errors_name_the_key_and_the_file(tmp_path):
    path = _write(tmp_path, "worn.txt", "0 0.001\n0.005 0\n0.01 x\n0.015 0\n")
    with pytest.raises(InputError) as err:
        tread_profile(WheelParams.from_mapping({"tread_profile": str(path)}))
    assert err.value.field == "wheel.tread_profile"
    assert err.value.message.startswith(f"{path}: line 3: not a number")


def test_the_command_line_refuses_a_bad_profile_with_one_line_and_status_2(tmp_path, capsys):
    path = _write(tmp_path, "worn.txt", "# units: mm\n0 1.75\n35 0.875\n70 \x07zero\n105 -0.875\n")
    out = tmp_path / "out"
    status = pipeline.main(["run", "--quick", "--quiet", "--set", f"wheel.tread_profile={path}",
                            "--out", str(out), "--until", "wheel-mesh"])
    err = capsys.readouterr().err
    assert status == 2
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith(f"error: wheel.tread_profile: {path}: line 4: not a number: '70 \\x07zero'")
    assert not out.exists() or not any(out.rglob("*.h5"))


def test_a_measured_profile_runs_as_the_tread(tmp_path):
    # the 1:40 cone file of the user guide (millimetres, comma separated) builds a wheel section
    path = _write(tmp_path, "measured.csv", _cone(","))
    params = WheelParams.from_mapping({"tread_profile": str(path)})
    surface = tread_profile(params)
    assert surface.name == str(path) and surface.height(0.070) == pytest.approx(0.0, abs=1e-9)
