"""Analyses that combine the model, the solvers and the result files: the nonlinear
response branch (:mod:`.response`) and the static deflection under base motion
(:mod:`.static`).

The names below are imported on first use (PEP 562), so that importing one analysis
module (``rotorsfd.analyses.checks`` for ``rotorsfd config check``) does not load the
harmonic-balance solvers and numba with the package.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rotorsfd.lazy import lazy_getattr

if TYPE_CHECKING:
    from rotorsfd.analyses.response import PointStability, ResponseResult, run_response
    from rotorsfd.analyses.static import StaticResult, run_static

#: name -> the module that defines it (deferred: numba, scipy)
LAZY: dict[str, str] = {
    **dict.fromkeys(("PointStability", "ResponseResult", "run_response"),
                    "rotorsfd.analyses.response"),
    **dict.fromkeys(("StaticResult", "run_static"), "rotorsfd.analyses.static"),
}

__all__ = ["PointStability", "ResponseResult", "StaticResult", "run_response", "run_static"]


#: the names of :data:`LAZY`, imported on first use and kept
__getattr__ = lazy_getattr(__name__, LAZY, globals())
