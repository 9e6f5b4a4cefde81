"""Triangle's command-line switches as ``triangulate`` keyword options, so that code
written for Triangle (or trimesh's ``triangle_args``) keeps working."""
from __future__ import annotations

import re

from .errors import CDTError

# switches that change nothing here: p (we always take a PLC), z (indices are
# ours), Q/V (quiet/verbose), e/n/B/P/N/E/I/O/A (output choices we always make)
_IGNORED = set("pzQVenBPNEIOA")
_NUMBER = r"(\d+(?:\.\d*)?|\.\d+)?"


def options_from_switches(switches: str) -> dict[str, float | bool | int]:
    """Translate a Triangle switch string into :func:`cdt_plugin.triangulate` options.

    ``q[angle]`` (20 degrees without a number) gives ``min_angle``, ``a<area>``
    ``max_area``, ``D`` ``conforming_delaunay``, ``Y`` ``split_boundary=False``,
    ``c`` ``keep_hull``, ``S<n>`` ``max_steiner``. Switches that only choose
    Triangle's output files are ignored; any other raises :class:`CDTError`.

    >>> options_from_switches("pq30a0.5Q")
    {'min_angle': 30.0, 'max_area': 0.5}
    >>> options_from_switches("pqDY")
    {'min_angle': 20.0, 'conforming_delaunay': True, 'split_boundary': False}
    """
    opts: dict[str, float | bool | int] = {}
    for m in re.finditer(r"([A-Za-z])" + _NUMBER, switches or ""):
        key, num = m.group(1), m.group(2)
        if key == "q":
            opts["min_angle"] = float(num) if num else 20.0
        elif key == "a" and num:
            opts["max_area"] = float(num)
        elif key == "D":
            opts["conforming_delaunay"] = True
        elif key == "Y":
            opts["split_boundary"] = False
        elif key == "c":
            opts["keep_hull"] = True
        elif key == "S" and num:
            opts["max_steiner"] = int(float(num))
        elif key not in _IGNORED:
            raise CDTError(f"Triangle switch {m.group(0)!r} in {switches!r} is not supported")
    leftover = re.sub(r"[A-Za-z]" + _NUMBER, "", switches or "")
    if leftover.strip():
        raise CDTError(f"cannot read Triangle switches {switches!r} (at {leftover.strip()!r})")
    return opts
