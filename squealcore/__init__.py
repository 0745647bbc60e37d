"""Shared infrastructure of the curve-squeal toolkit: input errors, HDF5 artefacts, study configuration.

Physics packages (``mesh``, ``fe``, ``waveguide``, ``interaction``) may import from here;
nothing here imports a physics package or ``pipeline``.
"""
