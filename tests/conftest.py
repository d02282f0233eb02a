import os
import pathlib
import tempfile

import numpy as np
import pytest
import scipy.linalg

import axojax as ax
from axojax.cache import CACHE_ENV

_OLD_CACHE_ENV = pytest.StashKey["str | None"]()


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
    (tests/test_notebooks.py), kept in pytest's cache directory
    (``.pytest_cache/d/jax-compilation-cache``; a temporary directory under
    ``-p no:cacheprovider``), not in the user's cache. Set here, before collection, so
    that no program is compiled before it.

    Much of the suite's time is compilation, and much of that is the same program compiled
    again: a model is a static argument hashed by identity, so every test that builds its
    own ``ax.models.seven()`` compiles ``dominant_mode`` anew, and every command and
    notebook starts from nothing. A cached program is the same program (results are
    identical; tests/test_cache.py), so every test checks what it checked before."""
    cache = getattr(config, "cache", None)
    path = cache.mkdir("jax-compilation-cache") if cache is not None else pathlib.Path(tempfile.mkdtemp(prefix="axojax-test-cache-"))
    config.stash[_OLD_CACHE_ENV] = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(path)
    ax.enable_compilation_cache(path)


def pytest_unconfigure(config):
    old = config.stash.get(_OLD_CACHE_ENV, None)
    if old is None:
        os.environ.pop(CACHE_ENV, None)
    else:
        os.environ[CACHE_ENV] = old
