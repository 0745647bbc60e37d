"""Wheel and rail profiles in one place: the shapes that the wheel and rail meshes are built on and
that the contact geometry searches, with their data files (``profiles/data/``).

Modules: :mod:`.curve` (a transverse profile z(y), its two-column text file and reader),
:mod:`.s1002` (the S1002 standard from its piecewise definition; data file ``data/s1002.txt``),
:mod:`.wheel_treads` (the registry of shipped tread profiles, ``[wheel] tread_profile``, and a pure
cone), :mod:`.rail_section` (rail section outlines: the registry of standard sections, their
published heads from ``data/rail_heads.json``, outline files, and the ``[rail]`` parameters),
:mod:`.rail_head` (the head surface of a section for contact, the rail inclination, the gauge point).

Below ``mesh`` (which meshes the wheel section around a tread profile and the rail outline) and
``contact_geometry`` (which searches contact on the same profiles); imports only ``squealcore``.
A new rail section or wheel profile is one data file here and one registration:
``PROFILES`` of :mod:`.rail_section`, ``TREADS`` of :mod:`.wheel_treads`.
"""
