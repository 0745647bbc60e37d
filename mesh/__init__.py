"""Geometry and meshing with gmsh: wheel cross-section, 3D wheel, rail cross-section."""
