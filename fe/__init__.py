"""In-house finite elements: 20-node hexahedron, axisymmetric harmonic element, modal solution,
receptances and Green's kernels, wheel rotation."""
