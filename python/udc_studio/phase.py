"""Phase masks (thesis chapter 4): two microlens arrays around a T-OLED, folded plates and the
allocation of folding wavelengths.

Each function evaluates the job of its name in-process (the one the ``udc-studio phase``
command of that name runs) and returns its result, the object its ``--json`` prints. Keyword
arguments are the job's parameters, the command's flags with ``_`` for ``-`` (``angle_deg=5``,
``preview=True``, ``photons=[250, 650]``); ``udc-studio phase psf --help`` lists them, with
units and defaults. Arrays in the result (a channel's ``psf``) are lists: ``numpy.asarray``
them.

>>> from udc_studio import phase
>>> r = phase.psf(preview=True)
>>> [c["name"] for c in r["channels"]]
['R', 'G', 'B']
"""

from __future__ import annotations

from typing import Any, Dict

from ._jobs import ParamValue, evaluate

__all__ = ["invertibility", "optimize", "psf", "restore"]


def psf(**params: ParamValue) -> Dict[str, Any]:
    """PSF per channel through the double MLA beside the bare T-OLED's (``phase psf``)."""
    return evaluate("phase-psf", params)


def invertibility(**params: ParamValue) -> Dict[str, Any]:
    """The invertibility matrix V over λ0 and λ (``phase invertibility``)."""
    return evaluate("phase-invertibility", params)


def optimize(**params: ParamValue) -> Dict[str, Any]:
    """Allocates folding wavelengths to lenslets (``phase optimize``, thesis Algorithm 1)."""
    return evaluate("phase-optimize", params)


def restore(**params: ParamValue) -> Dict[str, Any]:
    """A photo captured through the masks and restored: PSNR and SSIM per light level
    (``phase restore``; ``photo=PATH``, ``photons=[...]``, ``denoise="bm3d"``)."""
    return evaluate("phase-restore", params)
