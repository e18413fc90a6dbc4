"""Measured PSFs: a prototype's frames merged into a PSF set, compared with a design, the
display fitted to it, and a real capture restored with it (the book's chapter "Measuring a
prototype").

:func:`import_psf`, :func:`compare` and :func:`fit` evaluate ``psf import``, ``psf compare``
and ``psf fit`` in-process
and return the object their ``--json`` prints; :func:`load` reads a PSF set as numpy arrays;
:func:`restore` restores a real capture with one. Keyword arguments are the commands' flags
with ``_`` for ``-`` (``exposures_s=[0.001, 0.008]``, ``no_background=True``).

Camera RAW and DNG files: read them with ``rawpy`` and save linear 16-bit arrays::

    import rawpy, numpy as np
    with rawpy.imread("frame.dng") as raw:
        rgb = raw.postprocess(gamma=(1, 1), no_auto_bright=True, output_bps=16)
    np.save("frame.npy", rgb)
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Sequence, Union

from . import _native
from ._jobs import ParamValue, _plain, evaluate

__all__ = ["compare", "fit", "import_psf", "load", "restore"]

PathLike = Union[str, "os.PathLike[str]"]


def import_psf(
    frames: Union[PathLike, Sequence[PathLike]],
    out: PathLike,
    pixel_um: float,
    **params: ParamValue,
) -> Dict[str, Any]:
    """Merges one frame, or a bracket of exposures (``exposures_s=[…]``, ``dark=[…]``), into a
    PSF set written to ``out`` (``.npy`` with a ``.json`` sidecar); returns what was done per
    channel (``channels[i]["import"]``: the background, the centre, the clipped pixels, …)."""
    listed: List[PathLike] = [frames] if isinstance(frames, (str, os.PathLike)) else list(frames)
    args = {"frames": listed, "out": out, "pixel_um": pixel_um, **params}
    return dict(_native.psf_import({k: _plain(v) for k, v in args.items()}))


def compare(psf: PathLike, **params: ParamValue) -> Dict[str, Any]:
    """A PSF set beside a design (``preset=`` or ``design=`` a file) simulated at its pixel
    pitch: per channel the shift, the residual's share of the energy, the correlation and both
    radially-minimum MTFs with their AUC; ``out=`` a folder for the figures."""
    args = {"psf": psf, **params}
    return dict(_native.psf_compare({k: _plain(v) for k, v in args.items()}))


def fit(psf: PathLike, **params: ParamValue) -> Dict[str, Any]:
    """The display fitted to a PSF set, starting from a design (``preset=`` or ``design=`` a
    file): ``pitch_um``, ``open_fraction``, ``edge_bias_um``, ``rotation_deg``, ``defocus_um``
    and ``blur_um``, each ``{"value", "sigma"}``, with the residual before and after;
    ``out=`` a JSON file for the fitted design, ``window_px=`` the side fitted; ``backend=``
    ``"cpu"``, ``"gpu"`` or ``"auto"`` where the display's fine intensities are computed (the
    result's ``backend`` object then names the adapter)."""
    args = {"psf": psf, **params}
    return dict(_native.psf_fit({k: _plain(v) for k, v in args.items()}))


def load(path: PathLike, pixel_um: Union[float, None] = None) -> Dict[str, Any]:
    """A PSF set: ``pixel_um``, ``source`` (``measured`` or ``simulated``) and ``channels``,
    each with ``name``, ``wavelength_nm`` and ``psf`` (float64, summing to 1, the axis at
    ``[N//2, N//2]``)."""
    return dict(_native.read_psf(os.fspath(path), pixel_um))


def restore(psf: PathLike, image: PathLike, **params: ParamValue) -> Dict[str, Any]:
    """Restores a real capture ``image`` with the PSF set ``psf`` (``restore --psf``): BM3D at
    ``denoise_sigma2=`` when given, then Wiener or ``method="cg"``; ``truth=`` scores it."""
    return evaluate("restore", {"psf": psf, "image": image, **params})
