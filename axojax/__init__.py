"""axojax: differentiable finite-element mechanics of motile cilia.

Float64 is switched on at import (``jax_enable_x64``): the eigen-problems here span
ten orders of magnitude in stiffness and need it.

Unless ``AXOJAX_KEEP_XLA_FLAGS=1`` is set, importing axojax also makes XLA's CPU
runtime run one executable at a time and gives scipy's BLAS (which jaxlib's LAPACK
kernels call) a single thread: see :mod:`axojax._runtime` for why.
"""

from . import _runtime

_runtime.set_xla_flags()
_runtime.configure_jax()

from . import eigen, linalg, models  # noqa: E402
from .assembly import System, assemble  # noqa: E402
from .cache import enable_compilation_cache  # noqa: E402
from .critical import Critical, critical_force  # noqa: E402
from .eigen import Mode, dominant_mode, mode_shapes, spectrum  # noqa: E402
from .dynamics import Simulation, simulate  # noqa: E402
from . import orbits  # noqa: E402
from .orbits import LimitCycle, limit_cycle  # noqa: E402
from .fitting import FitResult, ShapeTarget, Target, fit, read_beat  # noqa: E402
from . import inverse  # noqa: E402
from .sweeps import SweepResult, sweep  # noqa: E402
from .params import PARAM_NAMES, Params  # noqa: E402
from .units import Units  # noqa: E402

__version__ = "0.1.0"

__all__ = ["enable_compilation_cache", "LimitCycle", "limit_cycle", "orbits", "FitResult", "inverse", "ShapeTarget", "Target", "fit", "read_beat", "Simulation", "simulate", "SweepResult", "sweep", "Critical", "critical_force", "eigen", "linalg", "Mode", "PARAM_NAMES", "Params", "System", "Units", "assemble", "dominant_mode", "mode_shapes", "models", "spectrum"]
