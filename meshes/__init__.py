"""The plate meshes (1D, r-z, box) and the VTK series writer. Imports nothing of
fpd."""
