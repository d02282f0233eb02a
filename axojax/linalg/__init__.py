"""Structured linear algebra: block-tridiagonal matrices (node-major finite-element
matrices) with pivoted LU and Cholesky factorisations in pure JAX, the same with a small border of extra
unknowns (Schur complement), and the Arnoldi process."""

from .blocktri import (
    BlockCholesky,
    BlockLU,
    BlockTridiagonal,
    LocalBlockLU,
    PackedBlockLU,
    cholesky,
    lu_factor,
    lu_factor_local,
    lu_factor_packed,
)
from .bordered import (
    Bordered,
    BorderedCholesky,
    BorderedLU,
    bordered,
    bordered_cholesky,
    bordered_lu,
)
from .krylov import arnoldi_steps

__all__ = [
    "BlockCholesky",
    "BlockLU",
    "BlockTridiagonal",
    "Bordered",
    "BorderedCholesky",
    "BorderedLU",
    "LocalBlockLU",
    "PackedBlockLU",
    "arnoldi_steps",
    "bordered",
    "bordered_cholesky",
    "bordered_lu",
    "cholesky",
    "lu_factor",
    "lu_factor_local",
    "lu_factor_packed",
]
