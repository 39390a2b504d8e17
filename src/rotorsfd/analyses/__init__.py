"""Analyses that combine the model, the solvers and the result files: the nonlinear
response branch (:mod:`.response`) and the static deflection under base motion
(:mod:`.static`)."""

from rotorsfd.analyses.response import PointStability, ResponseResult, run_response
from rotorsfd.analyses.static import StaticResult, run_static

__all__ = ["PointStability", "ResponseResult", "StaticResult", "run_response", "run_static"]
