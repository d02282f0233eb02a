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
"""

from __future__ import annotations

import os

OPT_OUT = "AXOJAX_KEEP_XLA_FLAGS"


def enabled() -> bool:
    return os.environ.get(OPT_OUT) != "1"


def set_xla_flags() -> None:
    """Before ``import jax``: single-threaded Eigen inside XLA's CPU executables."""
    flags = os.environ.get("XLA_FLAGS", "")
    if enabled() and "xla_cpu_multi_thread_eigen" not in flags:
        os.environ["XLA_FLAGS"] = (flags + " --xla_cpu_multi_thread_eigen=false").strip()


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
