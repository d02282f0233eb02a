"""Rebuild ``axojax/data/human_sperm.npz`` from a snapshot of the public repository
``polymaths-lab/3d-sperm-counter-vortices`` (CC0 1.0).

    git clone https://github.com/polymaths-lab/3d-sperm-counter-vortices SNAPSHOT
    python scripts/extract_human_sperm.py SNAPSHOT

Reads, from ``SNAPSHOT/Data0_Experimental Sperm/``:

- ``result/03_Head_Fixed_Frame_Method_Rotations_Traces_raw_5_Microns_Difraction_head_spin_rxmSSppxyz.mat``:
  cell arrays ``X``, ``Y``, ``Z`` (1 x 30 cells, um); only cell 8 (MATLAB's 1-based index,
  ``sp = 8`` in ``Smooth_Spline_Data.m``; Python index 7) is filled: 100 points (base to
  tip, smoothing-spline resampled, head-fixed frame, base at the origin) x 272 frames;
- ``FreeSperm_Frequency.mat``: ``HF_Freq(8)``, the head-frame beat frequency (Hz) the
  authors use (10.257 Hz = 31 cycles in 272 frames at 90 frames/s: their FFT peak).

The frame rate is not in the .mat files: the repository's code states it
(``Data1_Reconstruction/rxm_NumRecStokeslet_MobilityXNodes_Data.m``: ``dt = 1/90; ...
(framerate was 90fps)``).

Writes ``x_um``, ``y_um``, ``z_um`` as (frames, points) float32 (sub-nanometre rounding:
the tracking resolution is ~0.1 um), ``frame_rate_hz`` = 90 and
``published_frequency_hz`` = HF_Freq(8), compressed (about 0.3 MB).
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np
import scipy.io

CELL = 7  # Python index of MATLAB cell 8
FRAME_RATE_HZ = 90.0
SUBDIR = "Data0_Experimental Sperm"
CENTRELINES = "result/03_Head_Fixed_Frame_Method_Rotations_Traces_raw_5_Microns_Difraction_head_spin_rxmSSppxyz.mat"
OUT = pathlib.Path(__file__).resolve().parents[1] / "axojax" / "data" / "human_sperm.npz"


def extract(snapshot: pathlib.Path, out: pathlib.Path = OUT) -> pathlib.Path:
    folder = snapshot / SUBDIR
    xyz = scipy.io.loadmat(folder / CENTRELINES)
    freq = scipy.io.loadmat(folder / "FreeSperm_Frequency.mat")
    filled = [i for i in range(xyz["X"].size) if xyz["X"].flat[i].size]
    assert filled == [CELL], f"expected only cell {CELL} filled, found {filled}"
    arrays = {
        f"{c.lower()}_um": np.asarray(xyz[c].flat[CELL], dtype=np.float64).T.astype(np.float32)
        for c in "XYZ"
    }
    assert arrays["x_um"].shape == (272, 100), arrays["x_um"].shape
    np.savez_compressed(
        out,
        **arrays,
        frame_rate_hz=np.float64(FRAME_RATE_HZ),
        published_frequency_hz=np.float64(freq["HF_Freq"].flat[CELL]),
    )
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print(extract(pathlib.Path(sys.argv[1])))
