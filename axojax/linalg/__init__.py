"""Structured linear algebra: block-tridiagonal matrices (node-major finite-element
matrices) with pivoted LU and Cholesky factorisations in pure JAX, and the Arnoldi process."""

from .blocktri import BlockCholesky, BlockLU, BlockTridiagonal, cholesky, lu_factor
from .krylov import arnoldi_steps

__all__ = ["BlockCholesky", "BlockLU", "BlockTridiagonal", "arnoldi_steps", "cholesky", "lu_factor"]
