"""Rolling contact models: Kalker-type non-steady half-space (``halfspace``) and point contact (``point``)."""
