"""A sweep as an ``xarray.Dataset`` and a NetCDF file (optional: ``pip install 'axojax[netcdf]'``).

Dimensions are the sweep axes in axis order, with their values as coordinates; every
metric is a data variable with CF-style ``units`` and ``long_name``; ``classification``
and ``direction`` carry ``flag_values``/``flag_meanings`` (from the codes in the meta). The fixed parameters, units
and model go into flat attributes (NetCDF has no nested attributes) and, whole, into
``axojax_meta`` as the same JSON string the ``.npz`` file holds.
"""

from __future__ import annotations

import json
import pathlib
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import xarray

    from .result import SweepResult

VARIABLES: dict[str, tuple[str, str]] = {
    "eigenvalue_real": (
        "1/tau",
        "real part of the dominant eigenvalue (tau = c_n L^4 / EI, see tau_s)",
    ),
    "eigenvalue_imag": ("1/tau", "imaginary part of the dominant eigenvalue"),
    "growth_rate_per_s": ("1/s", "growth rate of the dominant mode"),
    "frequency_hz": ("Hz", "beat frequency of the dominant mode"),
    "wavelength_um": ("um", "wavelength of the dominant mode (NaN where it does not oscillate)"),
    "velocity_um_per_s": (
        "um/s",
        "wave speed of the dominant mode (NaN where it does not oscillate)",
    ),
    "out_of_plane_ratio": ("1", "out-of-plane share of the dominant mode's bending"),
    "direction": ("1", "direction of wave propagation"),
    "classification": ("1", "stability of the straight state"),
    "certified": (
        "1",
        "1 where the eigen-solver certified the dominant eigenvalue; 0 where the dense fallback supplied it",
    ),
    "result": ("1", "result code of the point's solve (axojax.results.RESULTS)"),
}


def require_xarray():
    """The xarray module, or ImportError with the install command."""
    try:
        import xarray
    except ImportError:
        raise ImportError(
            "NetCDF/xarray export needs xarray: pip install 'axojax[netcdf]'"
        ) from None
    return xarray


def to_xarray(result: "SweepResult") -> "xarray.Dataset":
    """The sweep as a labelled ``xarray.Dataset`` (one dimension per axis)."""
    xr = require_xarray()
    dims = tuple(result.coords)
    coords = {
        k: (
            k,
            np.asarray(v),
            {"units": "1", "long_name": f"{k} (dimensionless, docs/model.md section 1)"},
        )
        for k, v in result.coords.items()
    }
    data_vars = {}
    for name, values in result.data.items():
        units, long_name = VARIABLES.get(name, ("1", name))
        attrs: dict[str, Any] = {"units": units, "long_name": long_name}
        codes = result.meta.get(name)
        if isinstance(codes, dict):  # e.g. {"0": "stable", "1": "flutter", ...}
            flags = sorted(int(k) for k in codes)
            attrs["flag_values"] = np.asarray(flags, dtype=np.int8)
            attrs["flag_meanings"] = " ".join(codes[str(v)] for v in flags)
        data_vars[name] = (dims, np.asarray(values), attrs)
    meta = result.meta
    attrs = {
        "title": f"axojax sweep of the {meta.get('model', '?')} model",
        "axojax_meta": json.dumps(meta),
        "model": str(meta.get("model", "")),
        "axes": " ".join(dims),
    }
    for key in ("n_elements", "n_dof", "kl_ratio"):
        if meta.get(key) is not None:
            attrs[key] = meta[key]
    for key, value in meta.get("fixed", {}).items():
        attrs[f"fixed_{key}"] = value
    for key, value in meta.get("units", {}).items():
        attrs[f"units_{key}"] = value
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def to_netcdf(result: "SweepResult", path: str | pathlib.Path) -> None:
    """Write the sweep to a NetCDF file (xarray picks the engine: netCDF4, h5netcdf, or
    scipy's NetCDF3 writer, which the ``netcdf`` extra installs)."""
    from .._io import atomic_path

    with atomic_path(path) as tmp:
        to_xarray(result).to_netcdf(tmp)
