import os

import numpy as np
import pytest
import scipy.linalg

import axojax as ax


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


@pytest.fixture(scope="session", autouse=True)
def command_cache(tmp_path_factory):
    """`axojax` commands run by the tests as processes keep their compiled programs
    (axojax/cache.py) in a temporary directory, not in the user's cache."""
    old = os.environ.get("AXOJAX_CACHE_DIR")
    os.environ["AXOJAX_CACHE_DIR"] = str(tmp_path_factory.mktemp("compilation-cache"))
    yield
    if old is None:
        os.environ.pop("AXOJAX_CACHE_DIR")
    else:
        os.environ["AXOJAX_CACHE_DIR"] = old
