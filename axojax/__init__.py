"""axojax: differentiable finite-element mechanics of motile cilia.

Float64 is switched on at import (``jax_enable_x64``): the eigen-problems here span
ten orders of magnitude in stiffness and need it.
"""

import jax as _jax

_jax.config.update("jax_enable_x64", True)

from . import models  # noqa: E402
from .assembly import System, assemble  # noqa: E402
from .eigen import Mode, dominant_mode, mode_shapes, spectrum  # noqa: E402
from .params import PARAM_NAMES, Params  # noqa: E402
from .units import Units  # noqa: E402

__version__ = "0.1.0"

__all__ = ["Mode", "PARAM_NAMES", "Params", "System", "Units", "assemble", "dominant_mode", "mode_shapes", "models", "spectrum"]
