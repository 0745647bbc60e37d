"""Waveguide (2.5D) finite elements of the rail on a continuous support: waves, receptances and
moving Green's kernels."""
