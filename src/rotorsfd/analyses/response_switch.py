"""The period-2 branch of a response: ``rotorsfd response CONFIG --switch-at pd:N`` (or
plain ``N``; ``bp:N``, the second branch at a branch point, is
:mod:`rotorsfd.analyses.response_branch_switch`).

N counts the branch's period-doubling points from 1, in the order of the branch (the
order of the summary lines and of ``bifurcations.csv``'s ``period-doubling`` rows). At that
point :func:`~rotorsfd.harmonic.branch_switching.switch_period_doubling` continues the
2T-periodic branch in harmonics of ``Omega/2`` (default ``4 H``: the subharmonics k/2 of
the speed), within the main branch's parameter range, with the same element limit; its
legs' Floquet multipliers over 2T when the main branch has them.

Written next to the main branch as ``branch_period2.nc`` / ``branch_period2.csv`` and
drawn over its response figures by :class:`~rotorsfd.analyses.response_second_branch.
SecondBranchResult` (``at = "pd"``; the layout of both switches is in
:mod:`rotorsfd.analyses.response_second_branch`).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.analyses.response_second_branch import (
    OPTION,
    SecondBranchResult,
    needs_stability,
    second_branch_problem,
    where_words,
)
from rotorsfd.analyses.response_words import PARAMETER_UNITS, system_parameter
from rotorsfd.errors import ConfigError

if TYPE_CHECKING:
    from rotorsfd.analyses.response_result import ResponseResult

#: Odd amplitude of the period-2 branch's first point (scaled units: clearances), and the
#: longest step along it: the first point near the period doubling (lam - lam_pd ~ c a^2),
#: steps short of jumping back onto the period-1 branch (the paper case's subharmonic
#: part reaches ~0.05 C).
DELTA, STEP_MAX = 0.005, 0.02


def period_doublings(result: ResponseResult) -> list[int]:
    """Indices into ``result.bifurcations`` (and the stability's located bifurcations) of
    the period-doubling points, in the branch's order."""
    return [i for i, row in enumerate(result.bifurcations or ())
            if row["type"] == "period-doubling"]


def check_switch(result: ResponseResult, n: int, value: str = "") -> int:
    """The bifurcation index of the n-th period doubling (from 1); ConfigError naming
    ``--switch-at`` and ``value`` (default n) when the branch has none or fewer than n."""
    pds = period_doublings(result)
    shown: Any = value or n
    needs_stability(result, shown)
    if not pds:
        raise ConfigError(OPTION, shown, "the branch has no period-doubling point (no "
                          "Floquet multiplier crosses -1 over its range)")
    if not 1 <= n <= len(pds):
        where = ", ".join(f"{k + 1}: {where_words(result, result.bifurcations[i])}"
                          for k, i in enumerate(pds))
        raise ConfigError(OPTION, shown, f"must be 1..{len(pds)}, the branch's "
                          f"period-doubling points ({where})")
    return pds[n - 1]


def gap_notes(result: ResponseResult, given: float, hb: float) -> list[str]:
    """The summary's line when the period doubling of the period-2 HB equations (``hb``)
    is more than 1e-3 (relative) from the branch's (``given``): none otherwise."""
    gap = abs(hb - given) / abs(given)
    if gap <= 1e-3:
        return []
    name = "Omega~" if result.is_speed else result.parameter
    return [f"the period doubling of the period-2 HB equations is {gap:.1e} (relative) "
            f"from the branch's ({name} {_ratio(result, hb):.5g} against "
            f"{_ratio(result, given):.5g}): the branch's H does not resolve it; raise H "
            "(the check of the period doubling says by how much)"]


def _ratio(result: ResponseResult, lam: float) -> float:
    return lam / result.reference_speed if result.is_speed else lam


def run_switch(result: ResponseResult, number: int, *, harmonics: int | None = None,
               delta: float = DELTA, stability: bool = True, value: str = "",
               **continue_kw: Any) -> SecondBranchResult:
    """The period-2 branch at the ``number``-th period doubling of ``result`` (module
    docstring); ``harmonics`` of Omega/2 (default 4 H); ``continue_kw`` go to
    :func:`~rotorsfd.harmonic.branch_switching.switch_period_doubling`. ConfigError (the
    option named) when there is no such period doubling."""
    # deferred: harmonic.branch_switching (the HB switching machinery, only when switching)
    from rotorsfd.harmonic.branch_switching import switch_period_doubling

    i = check_switch(result, number, value)
    t0 = time.perf_counter()
    bif = result.info["stability"].bifurcations[i]
    located = bif.info.get("located")
    b = result.branch
    if located is not None:
        lam, X = float(located[0].lam), located[0].X
    else:
        lam = float(bif.lam)
        X = b.X[int(np.argmin(np.abs(b.lam - lam)))]
    kw = {"limit_max": result.info.get("limit_max", 1.0), "ds_max": STEP_MAX,
          **continue_kw}
    sw = switch_period_doubling(second_branch_problem(result), lam, X,
                                (float(b.lam.min()), float(b.lam.max())),
                                H=harmonics, delta=delta, **kw)
    attrs: dict[str, Any] = {"pd_parameter_given": sw.lam_given,
                             "pd_parameter_hb": sw.lam_bifurcation, "closed": int(sw.closed)}
    if sw.lam_rejoin is not None:
        attrs["rejoin_parameter"] = float(sw.lam_rejoin)
    out = SecondBranchResult(result, "pd", number, sw, result.bifurcations[i], lam,
                             attrs=attrs, notes=gap_notes(result, sw.lam_given,
                                                          sw.lam_bifurcation))
    if stability:
        out.with_stability(sw.stability(result.info.get("stability_options")))
    out.elapsed = time.perf_counter() - t0
    out.info["units"] = PARAMETER_UNITS[system_parameter(result.parameter)]
    return out
