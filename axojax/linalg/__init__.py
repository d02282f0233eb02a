"""Structured linear algebra: block-tridiagonal matrices (node-major finite-element
matrices) with pivoted LU and Cholesky factorisations in pure JAX."""

from .blocktri import BlockCholesky, BlockLU, BlockTridiagonal, cholesky, lu_factor

__all__ = ["BlockCholesky", "BlockLU", "BlockTridiagonal", "cholesky", "lu_factor"]
