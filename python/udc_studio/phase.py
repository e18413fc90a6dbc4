"""Phase masks (thesis chapter 4): two microlens arrays around a T-OLED, folded plates and the
allocation of folding wavelengths.

Each function runs the ``udc-studio phase`` command of its name in-process and returns the
object its ``--json`` prints. Keyword arguments are the command's flags with ``_`` for ``-``
(``angle_deg=5`` is ``--angle-deg 5``, ``preview=True`` is ``--preview``, a list repeats a flag);
``udc-studio phase psf --help`` lists them, with units and defaults. Arrays in the result
(a channel's ``psf``) are lists: ``numpy.asarray`` them.

>>> from udc_studio import phase
>>> r = phase.psf(preview=True)
>>> [c["name"] for c in r["channels"]]
['R', 'G', 'B']
"""

from __future__ import annotations

from typing import Any, Dict

from ._commands import FlagValue, run

__all__ = ["invertibility", "optimize", "psf", "restore"]


def psf(**flags: FlagValue) -> Dict[str, Any]:
    """PSF per channel through the double MLA beside the bare T-OLED's (``phase psf``)."""
    return run(["phase", "psf"], flags)


def invertibility(**flags: FlagValue) -> Dict[str, Any]:
    """The invertibility matrix V over λ0 and λ (``phase invertibility``)."""
    return run(["phase", "invertibility"], flags)


def optimize(**flags: FlagValue) -> Dict[str, Any]:
    """Allocates folding wavelengths to lenslets (``phase optimize``, thesis Algorithm 1)."""
    return run(["phase", "optimize"], flags)


def restore(**flags: FlagValue) -> Dict[str, Any]:
    """A photo captured through the masks and restored: PSNR and SSIM per light level
    (``phase restore``; ``photo=PATH``, ``photons=[...]``, ``denoise="bm3d"``)."""
    return run(["phase", "restore"], flags)
