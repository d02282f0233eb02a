"""Memory estimates of a model before it is built, and the one refusal rule.

A model (or a grid of them) whose estimated peak memory exceeds ``MEMORY_FRACTION`` of
the machine's physical memory is refused before any work, with the estimate: the
command line (``--elements``, a sweep's grid) and a fit spec's ``elements`` apply the
same estimate (:func:`model_bytes`) and the same rule (:func:`check_memory`).
"""

from __future__ import annotations

import os

from .eigen.solvers import Auto
from .models.section import CrossSection

MEMORY_FRACTION = 0.75
"""Share of the physical memory that an estimate may use."""
DENSE_SPECTRUM_BYTES = 96.0
"""Bytes per entry of an n x n matrix that the full dense spectrum of n unknowns needs
(pencil, reduced matrix, complex eigen-decomposition)."""


def physical_memory() -> int:
    """This machine's physical memory in bytes."""
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def check_memory(need_bytes: float, what: str) -> None:
    """Raise ``ValueError`` (one line: ``what`` and the estimate) when ``need_bytes``
    exceeds :data:`MEMORY_FRACTION` of the physical memory."""
    total = physical_memory()
    if need_bytes > MEMORY_FRACTION * total:
        raise ValueError(
            f"{what} needs about {need_bytes / 2**30:.3g} GiB of memory, more than "
            f"{MEMORY_FRACTION:.0%} of this machine's {total / 2**30:.3g} GiB"
        )


def dense_unknowns(section: CrossSection, n_elements: int) -> int:
    """Unknowns of the model (2 per node and transverse direction, clamped base)."""
    return section.n_filaments * section.n_dirs * 2 * n_elements


def model_bytes(section: CrossSection, n_elements: int) -> float:
    """Estimated peak memory (bytes) of building the model and one dominant eigenpair:
    the mesh's dense shape-function tables, the model's dense (n_fd, n_fd) coupling
    matrices (one per active pair), then either the dense pencil (12 n x n doubles: A,
    C, the complex eigen-decomposition) or, for models the Arnoldi solver takes
    (``Auto.min_arnoldi_dof`` unknowns or more), its block-tridiagonal factors and
    Krylov basis."""
    n_fd = section.n_filaments * section.n_dirs
    n = dense_unknowns(section, n_elements)
    build = 8.0 * (
        n_fd**2 * (2 + len(section.active_pairs))
        + (len(section.links) + 3 * len(section.active_pairs)) * n_fd
    )
    # the mesh: shape-function rows at 5 quadrature points per element over the 2 (n_e + 1)
    # nodal dofs (three of them), and the filament's dense matrices
    build += 8.0 * (3 * 5 * n_elements * 2 * (n_elements + 1) + 8 * (2 * n_elements) ** 2)
    if n < Auto().min_arnoldi_dof:
        return build + 96.0 * n**2
    block = 2 * n_fd
    return build + 8.0 * 16 * n_elements * block**2 + 16.0 * 96 * n


def check_model_size(section: CrossSection, n_elements: int) -> None:
    """Raise ``ValueError`` when the model's estimated memory (:func:`model_bytes`)
    exceeds the rule of :func:`check_memory`, before it is built."""
    n = dense_unknowns(section, n_elements)
    what = f"the {section.name!r} model with {n_elements} elements per filament ({n} unknowns)"
    check_memory(model_bytes(section, n_elements), what)
