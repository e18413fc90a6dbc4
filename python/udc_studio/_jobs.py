"""A job of the job layer, evaluated in-process: keyword arguments in, its result out."""

from __future__ import annotations

import math
import os
from typing import Any, Dict, Mapping

import numpy as np

from . import _native

#: What a parameter's value may be: a number, text, a path, a switch, or a list.
ParamValue = Any


def _plain(value: ParamValue) -> Any:
    """numpy scalars and arrays as Python numbers and lists; paths as text; a number that is not
    finite as its text (``nan``), so that its check refuses it by name instead of it being lost."""
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return value


def evaluate(job: str, params: Mapping[str, ParamValue]) -> Dict[str, Any]:
    """Evaluates job ``job`` (``"phase-psf"``, ``"sensor"``, … as a sweep spec names it) with
    these parameters and returns its result, the object its ``--json`` prints.

    Parameters are the job's, as the command line's flags without ``--`` and with ``_`` for
    ``-`` (``angle_deg=5``; a trailing ``_`` is dropped: ``lambda_``); ``None`` leaves one at
    its default, and so does ``False`` (a switch off; as in a sweep spec). An unknown parameter
    or a bad value raises ``ValueError`` naming it; an unreadable or unwritable file raises
    ``OSError``.
    """
    plain = {k: _plain(v) for k, v in params.items()}
    plain = {k: v for k, v in plain.items() if v is not None and v is not False}
    return _native.evaluate_job(job, plain)
