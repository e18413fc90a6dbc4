"""Spatially-varying gain and binning (thesis chapter 5) on an HDR scene.

:func:`simulate` evaluates the ``sensor`` job in-process (the one ``udc-studio sensor`` runs)
and returns the object its ``--json`` prints: per strategy its worst-ROI SSIM, PSNR (dB),
saturated fraction and the gain and bin maps. Keyword arguments are the job's parameters, the
command's flags with ``_`` for ``-`` (``sensor="nikon-z5"``, ``exposure="mean:0.05"``,
``max_side_px=256``); ``udc-studio sensor --help`` lists them.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Union

from . import _native
from ._jobs import ParamValue, evaluate

__all__ = ["pitch_figures", "simulate"]


def simulate(
    hdr: Union[str, "os.PathLike[str]"],
    strategy: Optional[str] = None,
    **params: ParamValue,
) -> Dict[str, Any]:
    """The sensor captures of an HDR scene (Radiance ``.hdr`` or OpenEXR), strategy by strategy.

    Without ``strategy`` the four strategies of Table 5.4; with one (``"vary-gain/vary-bin"``,
    ``"const-gain/bin-2"``, …) only that one, chosen among every strategy the command knows.
    """
    if strategy is None:
        return evaluate("sensor", {"hdr": hdr, **params})
    result = evaluate("sensor", {"hdr": hdr, "all_strategies": True, **params})
    names = [s["name"] for s in result["strategies"]]
    if strategy not in names:
        raise ValueError(f"strategy: unknown {strategy!r} (expected one of {', '.join(names)})")
    result["strategies"] = [s for s in result["strategies"] if s["name"] == strategy]
    return result


def pitch_figures(
    light_e_per_um2: float = 20.0,
    pitch_um: float = 1.0,
    sensor: str = "table54",
    snr_t: float = 4.0,
) -> List[Dict[str, Any]]:
    """Fig. 5.3 as data, the studio's Optimal pitch view: (a) the contrast of a sinusoid through
    pixels of ``pitch_um`` at ``light_e_per_um2`` (gain 1) against the noise times ``snr_t``, in
    electrons against cycles/µm, with the cutoff and Nyquist ``1/(2p)`` as ``annotations``; (b)
    the optimal pitch (µm) against log10 of the light, continuous and among the bin sizes.

    Each figure is a dict as :func:`udc_studio.sweep_figures` gives: ``title``, ``x`` and ``y``
    axes (``label``, ``unit``), ``series`` (``points`` as an N×2 array) and ``annotations``.
    """
    return list(_native.sensor_pitch_figures(light_e_per_um2, pitch_um, sensor, snr_t))
