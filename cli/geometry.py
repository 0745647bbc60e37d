"""The ``geometry`` command: ``python pipeline.py geometry [--config F] [--set k=v ...] [--json] [--out DIR]``.

Prints the wheel/rail contact(s) at the study's ``operating.lateral_displacement``, computed in
memory from the profiles (nothing is written); with ``--out DIR`` the ``contact-geometry`` stage is
also brought up to date in ``DIR`` (``contact_geometry.h5``, with the tables over the displacement
range). ``--json`` prints one JSON object: ``{"lateral_displacement": m, "contacts": [ContactPoint
as a dict, with "semi_axes": [a, b] m], "main_contact": index of the contact the interaction uses}``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from contact_geometry.study import main_contact, operating_contacts, study_geometry
from stages import engine
from stages.folder import FolderLock, folder_study

__all__ = ["add_args", "command", "format_contacts"]

#: Rows of the human-readable table: (label, ContactPoint attribute, scale, unit, format).
ROWS = (("wheel position from the flange back", "wheel_lateral", 1e3, "mm", ".2f"),
        ("rail position from the centre line (track)", "rail_lateral", 1e3, "mm", ".2f"),
        ("rail position in the section (y, z)", ("rail_section_lateral", "rail_section_height"), 1e3, "mm", ".2f"),
        ("rolling radius", "rolling_radius", 1e3, "mm", ".3f"),
        ("contact angle (track)", "contact_angle", 1.0, "rad", ".5f"),
        ("contact angle in the rail section", "rail_section_angle", 1.0, "rad", ".5f"),
        ("relative curvatures (long., lat.)", ("curvature_long", "curvature_lat"), 1.0, "1/m", ".4g"),
        ("Hertz semi-axes (a, b)", ("semi_axis_a", "semi_axis_b"), 1e3, "mm", ".3f"),
        ("normal force", "normal_force", 1e-3, "kN", ".3f"),
        ("geometric spin", "spin", 1.0, "1/m", ".5f"))


def add_args(parser):
    """Arguments of ``geometry``."""
    parser.add_argument("--config", help="study TOML file merged over the defaults (studies/paper.toml)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML; a bare word is a string); repeatable")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--out", help="also build the contact-geometry stage in this folder (default: write "
                                      "nothing)")


def format_contacts(contacts, main) -> str:
    """A small table per contact (mm, rad, kN), the one the interaction uses marked."""
    lines = [f"lateral displacement {contacts[0].lateral_displacement * 1e3:.3f} mm: {len(contacts)} contact(s)"]
    width = max(len(label) for label, *_ in ROWS)
    for k, contact in enumerate(contacts):
        used = " (used by the interaction)" if contact is main else ""
        lines.append(f"contact {k + 1}{used}")
        for label, attr, scale, unit, fmt in ROWS:
            attrs = attr if isinstance(attr, tuple) else (attr,)
            values = ", ".join(format(getattr(contact, a) * scale, fmt) for a in attrs)
            lines.append(f"  {label:<{width}}  {values} {unit}")
    return "\n".join(lines)


def command(args):
    """``geometry``: print the contact geometry at the operating displacement; returns the exit status."""
    study, _ = folder_study(args.out, args.config, args.quick, args.assignments, command="geometry")
    # both refuse displacements without contact (InputError) before anything is written
    contacts = operating_contacts(study)
    main = main_contact(contacts)
    if args.out is not None:
        study_geometry(study)
        with FolderLock(args.out, "pipeline.py geometry"):  # it builds, so it holds the folder's lock
            engine.run(study, Path(args.out), "contact-geometry", progress=False)
    if args.json:
        out = {"lateral_displacement": contacts[0].lateral_displacement,
               "contacts": [c.to_dict() for c in contacts], "main_contact": contacts.index(main)}
        print(json.dumps(out, indent=1, allow_nan=False))
    else:
        print(format_contacts(contacts, main))
    sys.stdout.flush()
    return 0
