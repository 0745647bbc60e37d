"""The S1002 wheel profile (EN 13715): re-exported from :mod:`mesh.s1002`.

The definition and the sampled data file (``mesh/data/s1002.txt``) live in ``mesh`` because the
wheel section is meshed with the S1002 running surface (``[wheel] tread_profile = "S1002"``) and
``contact_geometry`` imports ``mesh`` (not the other way round).
"""

from mesh.s1002 import (DATA_FILE, S1002_JOINTS_MM, S1002_TAPE_OFFSET, s1002_height, sample_s1002,
                        write_data_file)

__all__ = ["s1002_height", "S1002_JOINTS_MM", "S1002_TAPE_OFFSET", "DATA_FILE", "sample_s1002",
           "write_data_file"]
