"""Linear stability of the wheel–contact–rail loop: the screen, the rational fit of the rail and
the linear (rigid-rail and modal) analyses."""
