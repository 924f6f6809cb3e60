"""The plate models (lumped, fe1d, axisym, fe3d) and their kernels. May import
fpd.meshes; nothing heavy at import (FE modules load lazily)."""
