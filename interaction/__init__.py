"""Contact mechanics and the time-domain wheel/rail interaction."""
