"""Keyword arguments as the flags of a ``udc-studio`` command, run in-process."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping

import numpy as np

from . import _native

#: What a flag's value may be: a number, text, a path, a switch, or a list for a flag given
#: several times.
FlagValue = Any


def words(command: List[str], flags: Mapping[str, FlagValue]) -> List[str]:
    """``snr_db=[24, 28]`` → ``--snr-db 24 --snr-db 28``; ``preview=True`` → ``--preview``.

    ``None`` and ``False`` leave a flag out. A trailing underscore is dropped (``lambda_``).
    """
    out = list(command)
    for key, value in flags.items():
        flag = "--" + key.rstrip("_").replace("_", "-")
        if isinstance(value, np.bool_):
            value = bool(value)
        if value is None or value is False:
            continue
        if value is True:
            out.append(flag)
            continue
        for item in value if isinstance(value, (list, tuple)) else [value]:
            out += [flag, _text(item)]
    return out


def _text(value: FlagValue) -> str:
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    # numpy's scalars print as `np.float64(28.0)`: the plain number is the flag's value.
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, np.integer):
        return str(int(value))
    return str(value)


def run(command: List[str], flags: Mapping[str, FlagValue]) -> Dict[str, Any]:
    """Runs ``udc-studio COMMAND FLAGS --json`` in-process; returns the object it prints.

    A bad flag or value raises ``ValueError`` with the command line's message; an unreadable
    or unwritable file raises ``OSError``.
    """
    return json.loads(_native.run_json(words(command, flags)))
