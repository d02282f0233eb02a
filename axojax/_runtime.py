"""Process-wide runtime settings that axojax applies at import (opt out: ``AXOJAX_KEEP_XLA_FLAGS=1``).

1. ``--xla_cpu_multi_thread_eigen=false`` in ``XLA_FLAGS`` and synchronous CPU dispatch:
   one executable runs at a time (must happen before jax starts its CPU backend).
2. One thread for the BLAS that ships with scipy. jaxlib's CPU LAPACK kernels (LU,
   Cholesky, triangular solves, eig) call scipy's bundled OpenBLAS, whose worker threads
   busy-wait after every call. On a 2-core machine they fight XLA's own threads for the
   cores: a 280-unknown implicit simulation ran 1.8x slower alone (measured; beside a
   second process the same solve was ~7x slower, not all of it from BLAS). The matrices here are
   small (n <= a few hundred), so a single BLAS thread costs nothing. Only scipy's copy is
   limited (found with threadpoolctl); numpy's own BLAS keeps its threads.
3. jaxlib 0.10.x and 0.11.0 only: at least ``MIN_INTRA_OP_THREADS`` threads in XLA's CPU
   intra-op pool (the ``NPROC`` variable that XLA's CPU client reads; left alone when
   set). Those versions run a *batched* LAPACK call (eig, LU, Cholesky over a vmapped
   batch) by scheduling its matrices onto that pool and blocking the calling pool thread
   until they finish. The pool has one thread per core, so on a 2-core machine two such
   calls in flight (two devices' shards, or two independent calls in one executable)
   block both threads and nothing runs the scheduled work: a deadlock at 0 % CPU (gdb:
   both ``tf_XLAEigen`` threads in ``ParallelBatchMap`` / ``BlockingCounter::Wait``). A
   deadlock needs every pool thread blocked at once, so a wider pool removes it; the idle
   threads cost nothing. The sweep engine also never batches a LAPACK call
   (:mod:`axojax.sweeps.engine`), except through the structured solver's batched path
   (``ax.eigen.Arnoldi(batched=True)``), whose block factorisations are plain jnp and
   whose only library calls are the small projected eigen-problems. jaxlib 0.9.x has no such path and 0.11.1+ runs the
   batch inline.
"""

from __future__ import annotations

import os

OPT_OUT = "AXOJAX_KEEP_XLA_FLAGS"
MIN_INTRA_OP_THREADS = 16


def enabled() -> bool:
    return os.environ.get(OPT_OUT) != "1"


def set_xla_flags() -> None:
    """Before ``import jax``: single-threaded Eigen inside XLA's CPU executables (and, on
    jaxlib 0.10.x/0.11.0, a wider intra-op pool: :func:`widen_intra_op_pool`)."""
    flags = os.environ.get("XLA_FLAGS", "")
    if enabled() and "xla_cpu_multi_thread_eigen" not in flags:
        os.environ["XLA_FLAGS"] = (flags + " --xla_cpu_multi_thread_eigen=false").strip()
    widen_intra_op_pool()


def blocking_batched_lapack(jaxlib_version: str) -> bool:
    """Whether this jaxlib runs batched CPU LAPACK calls on the intra-op pool and blocks
    on it (0.10.x and 0.11.0; see the module docstring)."""
    parts = [int(x) if x.isdigit() else -1 for x in jaxlib_version.split("+")[0].split(".")[:3]]
    parts += [0] * (3 - len(parts))
    return parts[:2] == [0, 10] or parts == [0, 11, 0]


def widen_intra_op_pool() -> None:
    """Before jax starts its CPU backend: ``NPROC >= MIN_INTRA_OP_THREADS`` on the jaxlib
    versions of :func:`blocking_batched_lapack` (only where NPROC is not set)."""
    if not enabled() or "NPROC" in os.environ:
        return
    from importlib.metadata import PackageNotFoundError, version

    try:
        jaxlib_version = version("jaxlib")
    except PackageNotFoundError:
        return
    if blocking_batched_lapack(jaxlib_version) and (os.cpu_count() or 1) < MIN_INTRA_OP_THREADS:
        os.environ["NPROC"] = str(MIN_INTRA_OP_THREADS)


def configure_jax() -> None:
    """After ``import jax``: float64, synchronous CPU dispatch, one thread for scipy's BLAS."""
    import jax

    jax.config.update("jax_enable_x64", True)
    if not enabled():
        return
    jax.config.update("jax_cpu_enable_async_dispatch", False)
    limit_scipy_blas_threads()


def limit_scipy_blas_threads(threads: int = 1) -> int:
    """Limit the BLAS libraries loaded from scipy's wheel to ``threads``; returns how many
    libraries were limited (0 where scipy links a shared BLAS, e.g. conda builds)."""
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS so that threadpoolctl sees it)
    from threadpoolctl import ThreadpoolController

    controller = ThreadpoolController()
    scipy_libs = [lib for lib in controller.lib_controllers if lib.user_api == "blas" and os.sep + "scipy" in lib.filepath]
    for lib in scipy_libs:
        lib.set_num_threads(threads)
    return len(scipy_libs)
