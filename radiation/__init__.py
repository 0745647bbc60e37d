"""Sound radiation of the squealing wheel and the rail (issue 17).

Modules, one job each: ``acoustics`` (air, references), ``bands`` (one-third octaves,
A-weighting), ``surface`` (mode-shape surface integrals), ``wheel_vibration`` (per-pole modal
velocities from a case's force), ``efficiency`` (radiation efficiencies: wheel, rail),
``spectra`` (limit-cycle spectra), ``wheel_power``, ``rail_power``, ``receiver`` (pass-by
pressure), ``case_radiation`` (one case from arrays), ``grouping`` (cases per operating point),
``plots``, ``bem`` (bempp-cl reference, optional), ``bem_wheel`` and ``bem_compare`` (the fast model
against the BEM). The package reads no artefact: ``stages/radiation_inputs.py`` reads a case and its
structures, ``stages/radiation.py`` is the stage and ``stages/radiation_report.py`` the report section.
"""
