"""Quasi-static steady curving of a two-axle bogie (issue 35, item 1).

From a curve (radius, cant, speed) and a bogie (wheelbase, primary suspension, wheel/rail contact
geometry, friction) to each wheel's creepages, contacts, normal, creep and flange forces:
:func:`solve_bogie` with :class:`CurvingParams`. Physics package: imports ``squealcore``,
``contact_geometry`` and ``interaction`` only (docs/design.md, "Steady curving").

Modules: ``params`` (inputs), ``geometry`` (conical and profile contact geometry), ``loads``
(cant deficiency, load transfer), ``kinematics`` (creepages), ``creep`` (the point contact's
steady creep law), ``wheelset`` (forces on a wheelset), ``bogie`` (equilibrium and solution),
``operating`` (each wheel's operating point in the squeal study's conventions); ``linear_theory``
(the linear theory of curving by creep forces, an independent reference for the checks).
"""

from .bogie import RESIDUAL_TOLERANCE, CurvingError, solve_bogie, solve_wheelset
from .geometry import ConicalGeometry, ContactGeometry, ProfileGeometry, WheelsetGeometry, profile_geometry
from .loads import AxleLoads, axle_loads
from .operating import WHEEL_LABELS, WheelOperatingPoint, wheel_operating_points
from .params import CurvingParams

__all__ = ["CurvingParams", "solve_bogie", "solve_wheelset", "CurvingError", "RESIDUAL_TOLERANCE", "ConicalGeometry",
           "ProfileGeometry", "ContactGeometry", "WheelsetGeometry", "profile_geometry", "AxleLoads", "axle_loads",
           "WheelOperatingPoint", "wheel_operating_points", "WHEEL_LABELS"]
