"""axojax: differentiable finite-element mechanics of motile cilia.

Float64 is switched on at import (``jax_enable_x64``): the eigen-problems here span
ten orders of magnitude in stiffness and need it.

XLA's CPU runtime can wedge (hang at 0% CPU, waiting on its execution semaphore) when
several vmapped executables full of LAPACK eigen-solves are in flight at once. axojax
therefore, unless ``AXOJAX_KEEP_XLA_FLAGS=1`` is set, adds
``--xla_cpu_multi_thread_eigen=false`` to ``XLA_FLAGS`` and turns off CPU async
dispatch (``jax_cpu_enable_async_dispatch``), so one executable runs at a time. The
cost is small: the work is inside each executable's LAPACK calls.
"""

import os as _os

if _os.environ.get("AXOJAX_KEEP_XLA_FLAGS") != "1" and "xla_cpu_multi_thread_eigen" not in _os.environ.get("XLA_FLAGS", ""):
    _os.environ["XLA_FLAGS"] = (_os.environ.get("XLA_FLAGS", "") + " --xla_cpu_multi_thread_eigen=false").strip()

import jax as _jax  # noqa: E402

_jax.config.update("jax_enable_x64", True)
if _os.environ.get("AXOJAX_KEEP_XLA_FLAGS") != "1":
    _jax.config.update("jax_cpu_enable_async_dispatch", False)

from . import models  # noqa: E402
from .assembly import System, assemble  # noqa: E402
from .critical import Critical, critical_force  # noqa: E402
from .eigen import Mode, dominant_mode, mode_shapes, spectrum  # noqa: E402
from .dynamics import Simulation, simulate  # noqa: E402
from .fitting import FitResult, ShapeTarget, Target, fit, read_beat  # noqa: E402
from .sweeps import SweepResult, sweep  # noqa: E402
from .params import PARAM_NAMES, Params  # noqa: E402
from .units import Units  # noqa: E402

__version__ = "0.1.0"

__all__ = ["FitResult", "ShapeTarget", "Target", "fit", "read_beat", "Simulation", "simulate", "SweepResult", "sweep", "Critical", "critical_force", "Mode", "PARAM_NAMES", "Params", "System", "Units", "assemble", "dominant_mode", "mode_shapes", "models", "spectrum"]
