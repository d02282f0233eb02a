import os
import tempfile

# The command line keeps compiled programs on disk (axojax/cache.py); commands run by
# the tests keep theirs in a temporary directory, not in the user's cache.
os.environ.setdefault("AXOJAX_CACHE_DIR", tempfile.mkdtemp(prefix="axojax-test-cache-"))

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
