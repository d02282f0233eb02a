"""axojax: differentiable finite-element mechanics of motile cilia.

Float64 is switched on at import (``jax_enable_x64``): the eigen-problems here span
ten orders of magnitude in stiffness and need it.

Unless ``AXOJAX_KEEP_XLA_FLAGS=1`` is set, importing axojax also makes XLA's CPU
runtime run one executable at a time and gives scipy's BLAS (which jaxlib's LAPACK
kernels call) a single thread: see :mod:`axojax._runtime` for why.

The public names below are imported on first use (module ``__getattr__``), so that
``import axojax`` costs jax and nothing else: ``ax.sweep`` does not load diffrax, optax
or matplotlib. ``ax.simulate``, ``ax.fit``, ... work as before.
"""

import importlib
from typing import TYPE_CHECKING

from . import _runtime

_runtime.set_xla_flags()
_runtime.configure_jax()

__version__ = "0.1.0"

# public name -> (module, attribute); attribute None: the module itself. One line a name.
_LAZY = {
    "assemble": (".assembly", "assemble"),
    "System": (".assembly", "System"),
    "enable_compilation_cache": (".cache", "enable_compilation_cache"),
    "Critical": (".critical", "Critical"),
    "critical_force": (".critical", "critical_force"),
    "datasets": (".datasets", None),
    "Simulation": (".dynamics", "Simulation"),
    "simulate": (".dynamics", "simulate"),
    "eigen": (".eigen", None),
    "Mode": (".eigen", "Mode"),
    "dominant_mode": (".eigen", "dominant_mode"),
    "mode_shapes": (".eigen", "mode_shapes"),
    "nearest_mode": (".eigen", "nearest_mode"),
    "spectrum": (".eigen", "spectrum"),
    "FitResult": (".inverse", "FitResult"),
    "ShapeTarget": (".beats", "ShapeTarget"),
    "Target": (".beats", "Target"),
    "fit": (".inverse", "fit"),
    "compare": (".inverse", "compare"),
    "read_beat": (".beats", "read_beat"),
    "inverse": (".inverse", None),
    "posterior": (".inverse", "posterior"),
    "Posterior": (".inverse", "Posterior"),
    "linalg": (".linalg", None),
    "models": (".models", None),
    "orbits": (".orbits", None),
    "LimitCycle": (".orbits", "LimitCycle"),
    "limit_cycle": (".orbits", "limit_cycle"),
    "PARAM_NAMES": (".params", "PARAM_NAMES"),
    "Params": (".params", "Params"),
    "SweepResult": (".sweeps", "SweepResult"),
    "sweep": (".sweeps", "sweep"),
    "Units": (".units", "Units"),
    "Flagellum": (".units", "Flagellum"),
    "assembly": (".assembly", None),
    "beats": (".beats", None),
    "cache": (".cache", None),
    "critical": (".critical", None),
    "dynamics": (".dynamics", None),
    "fem": (".fem", None),
    "params": (".params", None),
    "sweeps": (".sweeps", None),
    "units": (".units", None),
    "waveform": (".waveform", None),
}

__all__ = sorted(_LAZY)  # noqa: PLE0605

if TYPE_CHECKING:  # the same names for static tools (type checkers, the API docs' griffe)
    from . import (
        assembly,
        beats,
        cache,
        critical,
        datasets,
        dynamics,
        eigen,
        fem,
        inverse,
        linalg,
        models,
        orbits,
        params,
        sweeps,
        units,
        waveform,
    )
    from .assembly import System, assemble
    from .beats import ShapeTarget, Target, read_beat
    from .cache import enable_compilation_cache
    from .critical import Critical, critical_force
    from .dynamics import Simulation, simulate
    from .eigen import Mode, dominant_mode, mode_shapes, nearest_mode, spectrum
    from .inverse import FitResult, Posterior, compare, fit, posterior
    from .orbits import LimitCycle, limit_cycle
    from .params import PARAM_NAMES, Params
    from .sweeps import SweepResult, sweep
    from .units import Flagellum, Units


def __getattr__(name: str):
    try:
        module, attribute = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'axojax' has no attribute {name!r}") from None
    value = importlib.import_module(module, __name__)
    if attribute is not None:
        value = getattr(value, attribute)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
