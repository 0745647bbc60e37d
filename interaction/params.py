"""The ``[operating]``, ``[time]`` and ``[simulation]`` study sections of the wheel/rail interaction."""

from __future__ import annotations

from dataclasses import dataclass

from interaction.wheel_models import REFERENCE, wheel_model_names
from squealcore.schema import param, section

__all__ = ["OperatingParams", "TimeParams", "SimulationParams"]



@section("operating")
@dataclass(frozen=True)
class OperatingParams:
    """Train speed, static wheel load and lateral position of the wheel on the rail."""

    speed: float = param(13.888888888888889, unit="m/s", low=0.0, high=150.0, low_open=True,
                         doc="Train speed (the default: 50 km/h, as in the paper).")
    wheel_load: float = param(50e3, unit="N", low=0.0, high=1e6, low_open=True,
                              doc="Static vertical wheel load.")
    lateral_displacement: float = param(0.0, unit="m", low=-0.02, high=0.02,
                                        doc="Lateral displacement of the wheel relative to the rail (positive: "
                                            "flange towards the rail's gauge face; 0: wheelset centred); the "
                                            "contact-geometry stage finds the contact there.")


@section("time")
@dataclass(frozen=True)
class TimeParams:
    """Time stepping of the interaction and of the Green's functions."""

    time_step: float = param(3.6e-5, unit="s", low=0.0, high=1e-3, low_open=True,
                             doc="Time step; the contact grid's dx = speed x time_step (0.5 mm by default).")
    duration: float = param(3.5, unit="s", low=0.0, high=100.0, low_open=True,
                            doc="Simulated time of each case.")
    wheel_kernel_duration: float = param(0.2, unit="s", low=0.0, high=10.0, low_open=True,
                                         doc="Length of the wheel's discrete Green's kernel stored in "
                                             "wheel_greens.h5.")


@section("simulation")
@dataclass(frozen=True)
class SimulationParams:
    """Wheel model, squeal criterion and solver tolerance of the cases."""

    wheel_model: str = param(REFERENCE, choices=wheel_model_names,
                             doc="Wheel model of the interaction: stationary, rotating load, or Eulerian.")
    rms_window: float = param(0.15, unit="s", low=0.0, high=100.0, low_open=True,
                              doc="Length of the end of the signal used for L_F2.")
    squeal_threshold: float = param(40.0, unit="dB", low=-300.0, high=300.0,
                                    doc="L_F2 (re 1 N) above it, with a limit cycle, counts as squeal.")
    squeal_min_frequency: float = param(1000.0, unit="Hz", low=0.0, high=1e5,
                                        doc="Lowest frequency of an oscillation meeting the squeal criterion that "
                                            "the summary and report class as squeal (curve squeal is tonal noise "
                                            "of about 1-10 kHz); below it: low-frequency oscillation. The squeal "
                                            "criterion itself (the squeal column) does not use it.")
    write_wav: bool = param(True, doc="Write a WAV (44.1 kHz) of the lateral force of squealing cases.")
    tolerance: float = param(1e-6, low=1e-12, high=1e-3,
                             doc="Relative tolerance of the contact solvers and of the coupling (of the wheel load).")
