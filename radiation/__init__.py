"""Sound radiation of the squealing wheel and the rail (issue 17).

Modules, one job each: ``acoustics`` (air, references), ``bands`` (one-third octaves,
A-weighting), ``surface`` (mode-shape surface integrals), ``wheel_vibration`` (per-pole modal
velocities from a case's force), ``efficiency`` (radiation efficiencies: wheel, rail),
``spectra`` (limit-cycle spectra), ``wheel_power``, ``rail_power``, ``receiver`` (pass-by
pressure), ``case_radiation`` (one case end to end), ``summary`` (summary.csv columns),
``report`` (report.md section), ``plots``, ``bem`` (bempp-cl reference, optional).
"""
