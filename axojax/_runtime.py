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
4. jaxlib 0.10.x only (where it was measured): ``--xla_cpu_use_fusion_emitters=false``,
   XLA's older (non-MLIR) code generator for fused CPU kernels. axojax's programs are
   many small loops (block factorisations, Arnoldi stages, Newton steps), and the newer
   emitters spend most of their compilation on them: the 64-point seven-filament Arnoldi
   program compiles ~1.7x faster without them, its gradient too, running as fast
   (``benchmarks/bench_compile.py`` compares the two in alternating fresh processes).
   Same results to the last bits (tests/house/test_compile_flags.py compares a process
   without these settings). Other versions are left alone: XLA aborts on a flag it does
   not know.
5. ``axojax compare`` (the linear one) only, set by the command line before jax starts:
   ``--xla_backend_optimization_level=0`` (:func:`compile_for_many_programs`). A
   comparison builds two programs per row and runs each for a second or two, so XLA's
   backend optimisation is most of its time: 345.6 s cold at the default level, 256.1 s
   at 0, 181.3 against 188.2 s warm (docs/benchmarks.md, "Where a comparison's time
   goes"). Rankings identical, fitted values within 8.3e-4 of their standard errors; the
   eigenvalues and their gradients equal to 1e-12 (the suite runs at this level,
   tests/house/test_compile_flags.py).
"""

from __future__ import annotations

import functools
import os

OPT_OUT = "AXOJAX_KEEP_XLA_FLAGS"
MIN_INTRA_OP_THREADS = 16


def enabled() -> bool:
    return os.environ.get(OPT_OUT) != "1"


EMITTER_FLAG = "--xla_cpu_use_fusion_emitters=false"


def set_xla_flags() -> None:
    """Before ``import jax``: single-threaded Eigen inside XLA's CPU executables, on
    jaxlib 0.10.x the older fusion emitters (item 4 of the module docstring), and, on
    jaxlib 0.10.x/0.11.0, a wider intra-op pool (:func:`widen_intra_op_pool`). A flag
    already in ``XLA_FLAGS`` is left as it is."""
    if not enabled():
        return
    flags = os.environ.get("XLA_FLAGS", "")
    if "xla_cpu_multi_thread_eigen" not in flags:
        flags = (flags + " --xla_cpu_multi_thread_eigen=false").strip()
    if "xla_cpu_use_fusion_emitters" not in flags and _version(_jaxlib_version())[:2] == [0, 10]:
        flags = (flags + " " + EMITTER_FLAG).strip()
    os.environ["XLA_FLAGS"] = flags
    widen_intra_op_pool()


FAST_COMPILE_FLAG = "--xla_backend_optimization_level=0"


def compile_for_many_programs() -> bool:
    """Before jax starts its CPU backend: XLA's backend optimisation level 0 (item 5 of the
    module docstring), unless ``XLA_FLAGS`` already sets a level, axojax's settings are
    opted out of, or the backend has started (then nothing changes). Returns whether the
    flag is now in effect for this process."""
    flags = os.environ.get("XLA_FLAGS", "")
    if "xla_backend_optimization_level" in flags:
        return FAST_COMPILE_FLAG in flags.split()
    if not enabled() or _backend_started():
        return False
    os.environ["XLA_FLAGS"] = (flags + " " + FAST_COMPILE_FLAG).strip()
    return True


def _backend_started() -> bool:
    from jax._src import xla_bridge

    return bool(getattr(xla_bridge, "_backends", None))


@functools.lru_cache(maxsize=1)
def _jaxlib_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("jaxlib")
    except PackageNotFoundError:
        return ""


def _version(text: str) -> list[int]:
    parts = [int(x) if x.isdigit() else -1 for x in text.split("+")[0].split(".")[:3]]
    return parts + [0] * (3 - len(parts))


def blocking_batched_lapack(jaxlib_version: str) -> bool:
    """Whether this jaxlib runs batched CPU LAPACK calls on the intra-op pool and blocks
    on it (0.10.x and 0.11.0; see the module docstring)."""
    parts = _version(jaxlib_version)
    return parts[:2] == [0, 10] or parts == [0, 11, 0]


def widen_intra_op_pool() -> None:
    """Before jax starts its CPU backend: ``NPROC >= MIN_INTRA_OP_THREADS`` on the jaxlib
    versions of :func:`blocking_batched_lapack` (only where NPROC is not set)."""
    if not enabled() or "NPROC" in os.environ:
        return
    jaxlib_version = _jaxlib_version()
    if (
        jaxlib_version
        and blocking_batched_lapack(jaxlib_version)
        and (os.cpu_count() or 1) < MIN_INTRA_OP_THREADS
    ):
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
    scipy_libs = [
        lib
        for lib in controller.lib_controllers
        if lib.user_api == "blas" and os.sep + "scipy" in lib.filepath
    ]
    for lib in scipy_libs:
        lib.set_num_threads(threads)
    return len(scipy_libs)
