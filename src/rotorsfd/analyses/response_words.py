"""A response branch in the user's terms: the continuation parameters' units and column
names, and why a branch did not start or stopped, naming the field to change (the
solver's own text in brackets)."""

from __future__ import annotations

import re

from rotorsfd.model.parameters import PARAMETERS, find_parameter
from rotorsfd.model.system import RotorSystem


#: SI unit of every continuation parameter (:data:`rotorsfd.model.parameters.PARAMETERS`).
class ParameterUnits(dict):
    """Parameter name -> SI unit; names outside the registry's entries (an element's field,
    ``elements.<name>.<field>``) are looked up by :func:`find_parameter`."""

    def __missing__(self, key: str) -> str:
        return find_parameter(key).unit


PARAMETER_UNITS = ParameterUnits({p.name: p.unit for p in PARAMETERS.values()})
FIELD = "analysis.response"


def failure_words(solver: str) -> str:
    """Why a branch stopped early, in the user's terms, from the continuation's message
    ("" when it says nothing more than the solver)."""
    if "max_points reached" in solver:
        return (f"{FIELD}.max_points reached (raise it, or raise {FIELD}.step_max to take "
                "larger steps)")
    if "stopped by the callback" in solver:
        return "stopped on request; the points so far are kept"
    if "minimum step" in solver:
        return (f"no converged point beyond it even at the smallest step {FIELD}.step_min "
                f"(a sharp turn of the branch: try a smaller {FIELD}.step_max or a fixed, "
                f"larger {FIELD}.harmonics)")
    return ""


def start_failure(system: RotorSystem, parameter: str, value: float, reference_speed: float,
                  limit_max: float | None, solver: str,
                  where: str = "the start of the range") -> str:
    """Why no periodic response was found at a branch's first point, in the user's terms
    (where, which limit or field, what to change), the solver's text in brackets."""
    name = system_parameter(parameter)
    if name == "speed":
        at = f"Omega~ = {value / reference_speed:.5g} ({value:.6g} rad/s)"
        first = f"{FIELD}.speed_range.start"
    else:
        unit = PARAMETER_UNITS[name]
        at = f"{parameter} = {value:.6g}" + ("" if unit == "1" else f" {unit}")
        first = f"{FIELD}.parameter_range"
    if "limit reached" in solver:
        limited = [e for e in system.elements if e.limit_label is not None]
        names = " or ".join(e.describe() for e in limited) or "an element"
        label = limited[0].limit_label if len(limited) == 1 else "its validity measure"
        bound = "" if limit_max is None else f" = {limit_max:g}"
        reason = (f"every Newton step from the linear response took {names} past "
                  f"{label}{bound}, the limit set by {FIELD}.max_eccentricity (the response "
                  f"there is too large for the element: start where it is smaller "
                  f"({first}), reduce the forcing, or raise max_eccentricity, up to 0.999)")
    elif "no convergence" in solver:
        reason = (f"Newton did not converge in {FIELD}.max_iterations iterations (raise "
                  f"it, or start where the response is closer to the linear one ({first}))")
    elif "singular" in solver:
        reason = ("the harmonic-balance equations are singular there (an undamped "
                  f"resonance of the linear rotor?): move {first}")
    else:
        reason = (f"the element forces could not be evaluated near the linear response "
                  f"(move {first})")
    return f"no periodic response at {where}, {at}: {reason} [solver: {one_line(solver)}]"


def one_line(text: str) -> str:
    """``text`` with its whitespace runs (newlines too) as single spaces."""
    return " ".join(text.split())


def system_parameter(path: str) -> str:
    """RotorSystem parameter of a config path ('base.pitching.value' -> 'base.pitching');
    ConfigError naming ``analysis.response.parameter`` for anything else."""
    return find_parameter(path, f"{FIELD}.parameter").name


def column_slug(text: str) -> str:
    """``"base.pitching.value"`` -> ``"base_pitching_value"``; ``"kg*m"`` -> ``"kg_m"``."""
    return re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", text)).strip("_")


# ---- quantities of a branch ----------------------------------------------------------------
