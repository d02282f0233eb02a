"""A sweep's labelled result: coordinates per axis, metric arrays, metadata; ``.npz`` I/O.

File layout (docs/cli.md): one coordinate array per axis named like the parameter flag
(``p``, ``ks``, ...), the metric arrays with one dimension per axis in axis order, and a
``meta`` JSON string with every fixed value, the axis order and the units. Wavelength and
velocity are NaN where the dominant mode does not oscillate. The ``result`` array holds
each point's :class:`axojax.results.RESULTS` code, and ``meta["result"]`` the code table
(``{"0": "successful", ...}``) it was written with.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
from typing import Any

import numpy as np

from .. import _io, results
from ..results import RESULTS

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
    "result",
)


@dataclasses.dataclass
class SweepResult:
    """Attributes:
    coords: axis name -> 1-D values, in axis order.
    data: metric name -> array of shape ``tuple(len(v) for v in coords.values())``
        (:data:`METRICS`; ``data["result"]``: the points' result codes, see
        :attr:`result`).
    meta: fixed parameters, units, model, axis order, code tables.
    """

    coords: dict[str, np.ndarray]
    data: dict[str, np.ndarray]
    meta: dict[str, Any]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.coords.values())

    @property
    def result(self) -> RESULTS:
        """Every point's :class:`axojax.results.RESULTS` code: one item holding an array
        of :attr:`shape` (as ``jax.vmap`` of :func:`axojax.dominant_mode` gives), so
        ``sweep.result == RESULTS.successful`` is a boolean array. A sweep without a
        ``result`` array (written before it was stored) gets ``successful`` where the
        eigenvalue is finite and ``nonfinite`` elsewhere."""
        if "result" in self.data:
            return results.recode(
                self.data["result"], self.meta.get("result") or results.code_names()
            )
        finite = np.isfinite(np.asarray(self.data["eigenvalue_real"]))
        return results.from_codes(
            np.where(finite, results.codes(RESULTS.successful), results.codes(RESULTS.nonfinite))
        )

    @property
    def message(self) -> str:
        """One line on :attr:`result`: ``"all N successful"`` or how many points failed,
        and why (:func:`axojax.results.summary`)."""
        return results.summary(self.result)

    def to_json(self) -> dict[str, Any]:
        """Plain-Python summary: ``model``, ``axes`` (``{name: [first, last, n]}``),
        ``shape``, ``points``, ``counts`` (points per classification), ``solver`` (as in
        ``axojax sweep --json``, which adds where and how the run went), and ``results``
        (points per result name)."""
        cls = np.asarray(self.data["classification"])
        names, counts = np.unique(results.codes(self.result), return_counts=True)
        return results.jsonable(
            {
                "model": self.meta.get("model"),
                "axes": {k: [float(v[0]), float(v[-1]), len(v)] for k, v in self.coords.items()},
                "shape": list(self.shape),
                "points": int(np.prod(self.shape)),
                "counts": {
                    name: int(np.sum(cls == code))
                    for code, name in enumerate(("stable", "flutter", "divergence"))
                },
                "solver": self.meta.get("solver"),
                "results": {results.NAMES[int(k)]: int(c) for k, c in zip(names, counts)},
            }
        )

    def save(self, path: str | pathlib.Path) -> None:
        """Write the sweep to ``path`` (``.npz``, any case; written whole, see
        :mod:`axojax._io`). Raises ``ValueError`` for another suffix or a directory that
        does not take the file (:func:`axojax._io.check_output_path`)."""
        path = _io.check_output_path(path, (".npz",))
        arrays = {**{k: np.asarray(v) for k, v in self.coords.items()}, **self.data}
        meta = dict(self.meta)
        if "result" in self.data:
            meta.setdefault("result", results.code_names())
        arrays["meta"] = np.array(json.dumps(meta))
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
        """Read what :meth:`save` wrote; result codes are mapped to this installation's
        (by name, through ``meta["result"]``)."""
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            coords = {k: f[k] for k in meta["axes"]}
            data = {k: f[k] for k in METRICS if k in f}
        if "result" in data:
            table = meta.get("result") or results.code_names()
            data["result"] = results.codes(results.recode(data["result"], table)).astype(np.int8)
            meta["result"] = results.code_names()
        return cls(coords, data, meta)

    @classmethod
    def read(cls, path: str | pathlib.Path) -> "SweepResult":
        """:meth:`load`, the file checked whole: its growth rate, frequency and
        classification there, every metric on the grid of the coordinates; a file that is
        not is one :class:`~axojax.results.ResultFileError` naming it."""

        def checked(path):
            obj = cls.load(path)
            shape = obj.shape
            need = ("growth_rate_per_s", "frequency_hz", "classification")
            missing = [k for k in need if k not in obj.data]
            if missing:
                raise results.ResultFileError(
                    f"{str(path)!r} is a sweep file without its {missing[0]!r} array"
                )
            metrics = {k: obj.data[k] for k in METRICS if k in obj.data}
            results.check_arrays(
                path,
                "sweep",
                {**{k: np.asarray(v) for k, v in obj.coords.items()}, **metrics},
                {
                    **{k: (len(v),) for k, v in obj.coords.items()},
                    **{k: shape for k in metrics},
                },
            )
            return obj

        return results.read_checked(path, "sweep", checked)
