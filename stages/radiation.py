"""``radiation`` stage: the sound of one case, after ``simulate``.

Reads ``cases/<id>.h5`` and the structural artefacts of its variant and writes
``radiation/<id>.h5`` (schema ``radiation``):

datasets ``band_centres`` (nb,) Hz, ``wheel/band_power``, ``rail/band_power`` (nb,) W,
``wheel/band_pressure2``, ``rail/band_pressure2`` (nb,) Pa² at the pass-by receiver,
``band_LpA`` (nb,) dB(A), ``poles/frequency`` Hz, ``poles/power`` W, ``poles/input_power`` W,
``poles/harmonic``, ``poles/mode``; attributes ``L_W`` (dB re 1 pW, wheel + rail), ``L_W_wheel``,
``L_W_rail``, ``L_pA`` (dB(A) re 20 µPa), ``input_power`` (W), ``wheel_power``, ``rail_power`` (W),
``wheel_model``, ``case_id``; and, if the case squeals and ``simulation.write_wav`` is set,
``sounds/<id>_receiver.wav``, the pressure at the receiver (peak-normalised, like the force WAV).
The physics is in the ``radiation`` package (docs/design.md, "Radiation").
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

from squealcore.artefacts import ArtefactError, add_dataset, open_artefact, read_dataset
from stages.cases import write_wav

logger = logging.getLogger(__name__)

RADIATION_VERSION = 2
"""Schema version of ``radiation/<id>.h5`` (2: coincident poles of a wheel model merged)."""

#: Sections the stage reads (the limit-cycle window, the wheel load, the WAV switch).
RADIATION_SECTIONS = ("simulation", "operating")
#: Structural artefacts of the variant it reads, besides the case.
RADIATION_INPUTS = ("wheel_mesh.h5", "wheel_modes.h5", "wheel_greens.h5", "rail_mesh.h5", "rail_greens.h5")


def radiation_path(out_dir, case_id):
    """``out_dir/radiation/<case_id>.h5``."""
    return Path(out_dir) / "radiation" / f"{case_id}.h5"


def build_radiation(ctx):
    """Compute and write the radiation artefact of one case (``ctx.inputs``: ``case``, ``variant``)."""
    # the radiation package pulls in numba-compiled code (~2 s), which `pipeline.py status` and
    # input errors, which import the engine and so this module, should not pay
    from stages.radiation_inputs import radiate_case  # lazy: ~2 s (numba)

    study = ctx.study
    case_path = Path(ctx.inputs["case"])
    result = radiate_case(case_path, ctx.inputs["variant"], study["operating"]["wheel_load"],
                          study["simulation"]["rms_window"])
    with open_artefact(case_path, "case") as f:
        case_id = str(f.attrs["case_id"])
        wheel_model = str(f.attrs["wheel_model"])
        squeal = bool(f.attrs["squeal"])
    with ctx.writer() as f:
        f.attrs.update({"case_id": case_id, "wheel_model": wheel_model, "L_W": result.L_W,
                        "L_W_wheel": result.L_W_wheel, "L_W_rail": result.L_W_rail, "L_pA": result.L_pA,
                        "input_power": result.input_power, "wheel_power": result.wheel_power,
                        "rail_power": result.rail_power})
        add_dataset(f, "band_centres", result.band_centres, "Hz")
        add_dataset(f, "wheel/band_power", result.wheel_band_power, "W")
        add_dataset(f, "rail/band_power", result.rail_band_power, "W")
        add_dataset(f, "wheel/band_pressure2", result.wheel_band_pressure2, "Pa^2")
        add_dataset(f, "rail/band_pressure2", result.rail_band_pressure2, "Pa^2")
        add_dataset(f, "band_LpA", result.band_pressure_level(a_weighted=True), "dB")
        add_dataset(f, "poles/frequency", result.pole_frequency, "Hz")
        add_dataset(f, "poles/power", result.pole_power, "W")
        add_dataset(f, "poles/input_power", result.pole_input_power, "W")
        add_dataset(f, "poles/harmonic", result.pole_harmonic, "")
        add_dataset(f, "poles/mode", result.pole_mode, "")
    if squeal and study["simulation"]["write_wav"]:
        write_wav(str(ctx.out_dir / "sounds" / f"{case_id}_receiver.wav"),
                  result.wheel_pressure + result.rail_pressure, result.time_step)
    return {"L_W": result.L_W, "L_pA": result.L_pA}


def read_radiation(path):
    """The levels of a radiation artefact: dict of its attributes and band arrays."""
    with open_artefact(path, "radiation", RADIATION_VERSION) as f:
        out = {key: f.attrs[key] for key in ("case_id", "wheel_model", "L_W", "L_W_wheel", "L_W_rail", "L_pA",
                                             "input_power", "wheel_power", "rail_power")}
        out["band_centres"] = read_dataset(f, "band_centres", "Hz", (None,))
        for name in ("wheel/band_power", "rail/band_power"):
            out[name] = read_dataset(f, name, "W", (None,))
        for name in ("wheel/band_pressure2", "rail/band_pressure2"):
            out[name] = read_dataset(f, name, "Pa^2", (None,))
        out["band_LpA"] = read_dataset(f, "band_LpA", "dB", (None,))
        out["pole_frequency"] = read_dataset(f, "poles/frequency", "Hz", (None,))
        out["pole_power"] = read_dataset(f, "poles/power", "W", (None,))
        out["pole_harmonic"] = read_dataset(f, "poles/harmonic", "", (None,))
    out["case_id"] = str(out["case_id"])
    out["wheel_model"] = str(out["wheel_model"])
    return out


#: The levels a case summary takes from its radiation artefact (``summary.csv`` columns).
SUMMARY_LEVELS = ("L_W", "L_pA")


def radiation_levels(case_path):
    """``{"L_W": dB re 1 pW, "L_pA": dB(A)}`` of a case, from ``radiation/<id>.h5`` beside its
    ``cases/<id>.h5``; NaN where that artefact is missing or unreadable (the stage did not run or
    failed for the case).

    Parameters
    ----------
    case_path : path
        ``<study folder>/cases/<id>.h5``.
    """
    case_path = Path(case_path)
    try:
        levels = read_radiation(radiation_path(case_path.parent.parent, case_path.stem))
    except (ArtefactError, OSError, KeyError):
        return {name: math.nan for name in SUMMARY_LEVELS}
    return {name: float(levels[name]) for name in SUMMARY_LEVELS}
