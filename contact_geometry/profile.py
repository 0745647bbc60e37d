"""Transverse profiles z(y) of wheels and rails, and their two-column text files.

The implementation lives in :mod:`mesh.profile_curve`: the wheel section (package ``mesh``)
builds its running surface from a tread profile, and ``contact_geometry`` imports ``mesh``, so the
profile type sits in the lower package and is re-exported here under the name the contact code
uses. File format, frames and checks: see :mod:`mesh.profile_curve`.
"""

from mesh.profile_curve import MIN_POINTS, Profile, read_profile, write_profile

__all__ = ["Profile", "read_profile", "write_profile", "MIN_POINTS"]
