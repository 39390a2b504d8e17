"""The paper's case studies (Zhang et al. 2025), their runs and the comparison report."""

from rotorsfd.paper.cases import CASES, FIGURES, Case, FigureSpec
from rotorsfd.paper.claims import CLAIMS, Claim
from rotorsfd.paper.run import Outcome, PaperResult, run_case, run_cases, run_paper

__all__ = ["CASES", "CLAIMS", "FIGURES", "Case", "Claim", "FigureSpec", "Outcome",
           "PaperResult", "run_case", "run_cases", "run_paper"]
