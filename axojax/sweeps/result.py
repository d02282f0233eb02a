"""A sweep's labelled result: coordinates per axis, metric arrays, metadata; ``.npz`` I/O.

File layout (INTERFACE.md): one coordinate array per axis named like the parameter flag
(``p``, ``ks``, ...), the metric arrays with one dimension per axis in axis order, and a
``meta`` JSON string with every fixed value, the axis order and the units. Wavelength and
velocity are NaN where the dominant mode does not oscillate.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
from typing import Any

import numpy as np

from .. import _io

METRICS = (
    "eigenvalue_real",
    "eigenvalue_imag",
    "growth_rate_per_s",
    "frequency_hz",
    "wavelength_um",
    "velocity_um_per_s",
    "out_of_plane_ratio",
    "direction",
    "classification",
    "certified",
)


@dataclasses.dataclass
class SweepResult:
    """Attributes:
    coords: axis name -> 1-D values, in axis order.
    data: metric name -> array of shape ``tuple(len(v) for v in coords.values())``.
    meta: fixed parameters, units, model, axis order.
    """

    coords: dict[str, np.ndarray]
    data: dict[str, np.ndarray]
    meta: dict[str, Any]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.coords.values())

    def save(self, path: str | pathlib.Path) -> None:
        """Write the sweep to ``path`` (``.npz``, any case; written whole, see
        :mod:`axojax._io`). Raises ``ValueError`` for another suffix or a directory that
        does not take the file (:func:`axojax._io.check_output_path`)."""
        path = _io.check_output_path(path, (".npz",))
        arrays = {**{k: np.asarray(v) for k, v in self.coords.items()}, **self.data}
        arrays["meta"] = np.array(json.dumps(self.meta))
        with _io.atomic_path(path) as tmp:
            np.savez(tmp, **arrays)

    def to_xarray(self):
        """The sweep as an ``xarray.Dataset`` (needs ``axojax[netcdf]``; see
        :mod:`axojax.sweeps.netcdf`)."""
        from .netcdf import to_xarray

        return to_xarray(self)

    def to_netcdf(self, path: str | pathlib.Path) -> None:
        """Write the sweep to NetCDF (needs ``axojax[netcdf]``)."""
        from .netcdf import to_netcdf

        to_netcdf(self, path)

    @classmethod
    def load(cls, path: str | pathlib.Path) -> "SweepResult":
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            coords = {k: f[k] for k in meta["axes"]}
            data = {k: f[k] for k in METRICS if k in f}
        return cls(coords, data, meta)
