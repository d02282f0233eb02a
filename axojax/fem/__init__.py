"""Finite elements: cubic Hermite shape functions and filament-level matrices.

Everything here is *static structure*: it depends on the mesh (number of elements)
and on optional x-profiles, never on traced parameters, and is computed once with
numpy when a model is built.
"""

from .filament import FilamentMatrices, Profiles, filament_matrices
from .hermite import Mesh, interpolation_matrix, make_mesh

__all__ = [
    "Mesh",
    "make_mesh",
    "interpolation_matrix",
    "FilamentMatrices",
    "Profiles",
    "filament_matrices",
]
