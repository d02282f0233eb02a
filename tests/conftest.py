import os
import pathlib
import shutil
import tempfile

import jax
import numpy as np
import pytest
import scipy.linalg

import axojax as ax
from axojax.cache import CACHE_ENV, WARM_SUBDIR

# The suite compiles with XLA's CPU backend at optimisation level 0. XLA reads XLA_FLAGS
# when its backend starts, at the first computation, which comes after this module is
# imported; the commands and notebook kernels the tests start inherit the setting. Most of
# the suite's time is compilation and its programs run briefly, so less optimised machine
# code makes it faster. (`import axojax` above has already chosen XLA's older CPU fusion
# emitters where that pays, axojax/_runtime.py; the suite keeps that choice.) The level
# changes how the machine code is optimised, so results can differ in the last bits (an
# iterative solve may stop one step apart), not in what is computed:
# tests/house/test_compile_flags.py checks eigenvalues and gradients against a process with
# XLA's default flags to 1e-12. Opt out with AXOJAX_TEST_FULL_OPTIMISATION=1; benchmarks/
# never set it.
LEVEL_FLAG = "--xla_backend_optimization_level=0"
SUITE_XLA_FLAGS = LEVEL_FLAG
if not os.environ.get(
    "AXOJAX_TEST_FULL_OPTIMISATION"
) and "xla_backend_optimization_level" not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " " + SUITE_XLA_FLAGS).strip()

_OLD_CACHE_ENV = pytest.StashKey["str | None"]()

# pytest.approx of a jax array depends on how each pytest release inspects it (9.2.0 reads
# `.flat`, which jax arrays refuse): tests hand it plain floats or numpy arrays only. This
# guard makes a jax array fail the same way under every pytest release, with the fix named.
_pytest_approx = pytest.approx


def _approx_of_plain_numbers(expected, *args, **kwargs):
    if isinstance(expected, jax.Array) or (
        isinstance(expected, (list, tuple)) and any(isinstance(e, jax.Array) for e in expected)
    ):
        raise TypeError(
            "pytest.approx of a jax array: pass float(x) or np.asarray(x) (its handling "
            "changes between pytest releases)"
        )
    return _pytest_approx(expected, *args, **kwargs)


pytest.approx = _approx_of_plain_numbers


def scipy_dominant(model, params):
    """Independent dominant eigenvalue: scipy's generalized eig of the assembled matrices."""
    s = ax.assemble(model, params)
    lam = scipy.linalg.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
    lam = lam[np.argsort(-lam.real)]
    top = lam[0]
    return complex(top.real, abs(top.imag))


def scipy_max_real(model, params):
    s = ax.assemble(model, params)
    lam = scipy.linalg.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
    return lam[np.argmax(lam.real)]


@pytest.fixture(scope="session")
def seven():
    return ax.models.seven()


def pytest_configure(config):
    """One persistent cache of compiled programs (axojax/cache.py) for the test process,
    the `axojax` commands the tests run as processes and the notebooks' kernels
    (tests/house/test_notebooks.py), kept in pytest's cache directory
    (``.pytest_cache/d/jax-compilation-cache``; a temporary directory under
    ``-p no:cacheprovider``), not in the user's cache. Set here, before collection, so
    that no program is compiled before it.

    Much of the suite's time is compilation, and much of that is the same program compiled
    again: a model is a static argument hashed by identity, so every test that builds its
    own ``ax.models.seven()`` compiles ``dominant_mode`` anew, and every command and
    notebook starts from nothing. A cached program is the same program (results are
    identical; tests/house/test_compilation_cache.py), so every test checks what it checked before."""
    cache = getattr(config, "cache", None)
    path = (
        cache.mkdir("jax-compilation-cache")
        if cache is not None
        else pathlib.Path(tempfile.mkdtemp(prefix="axojax-test-cache-"))
    )
    if not hasattr(config, "workerinput"):  # the controller, before any worker starts:
        # the posterior's warm states (axojax/inverse/sampling/_warm_cache.py) kept by the CLI's
        # tests in this directory are dropped, so that each run executes their start-up
        # code (tests/sampling/test_warm_cache.py checks loading them within a run).
        shutil.rmtree(path / WARM_SUBDIR, ignore_errors=True)
    config.stash[_OLD_CACHE_ENV] = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(path)
    # the suite's workers already fill the cores: a comparison's rows one at a time there
    # (tests/comparison/test_schedule.py runs them two at a time and checks they agree)
    os.environ.setdefault("AXOJAX_COMPARE_WORKERS", "1")
    # unbounded: the suite's own folder, read by several workers (no eviction lock to share)
    ax.enable_compilation_cache(path, max_mb=-1)


def pytest_unconfigure(config):
    old = config.stash.get(_OLD_CACHE_ENV, None)
    if old is None:
        os.environ.pop(CACHE_ENV, None)
    else:
        os.environ[CACHE_ENV] = old


@pytest.hookimpl(tryfirst=True)  # before xdist's own, which reads the marks
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist (``-n``, README), one test module runs on one worker, so a
    module's fixtures are computed once (``--dist loadgroup`` with one group per module);
    the notebooks are the exception: each is its own group, being long and independent.
    The notebooks run first: with ``--no-loadscope-reorder`` (addopts; xdist would otherwise
    put groups with many tests first, and the one-test notebook groups last) workers take
    groups in collection order, so the long ones start early and the short modules fill
    the end instead of one worker finishing alone."""

    def notebook(item):
        return item.module.__name__.endswith("test_notebooks")

    for item in items:
        if item.get_closest_marker("xdist_group") is None:
            item.add_marker(
                pytest.mark.xdist_group(item.nodeid if notebook(item) else item.module.__name__)
            )
    items.sort(key=lambda item: not notebook(item))  # stable: modules stay contiguous


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop jax's in-memory compiled programs after each test module. A worker runs
    hundreds of modules and kept every program it compiled: 7-8 GB per worker by the
    end of the suite, two workers of the 24 GB machine CI has, and XLA aborted while
    compiling at that size (twice on 2026-12-06, in different modules). A program needed
    again comes back from the persistent cache on disk (``pytest_configure``)."""
    yield
    jax.clear_caches()


@pytest.fixture(autouse=True)
def _no_progress(monkeypatch):
    """Progress off in every test (``AXOJAX_PROGRESS=0``): off a terminal a run longer
    than 2 s writes plain progress lines to stderr (axojax/_progress.py), and the tests
    that check a command's error is one line would pass or fail by the machine's speed.
    tests/house/test_progress.py sets or removes the variable where it checks progress."""
    monkeypatch.setenv("AXOJAX_PROGRESS", "0")
